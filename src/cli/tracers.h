// The tracers a user can pick with --tracer, by name.
#pragma once

#include "render/render.h"
#include "scene/scene.h"
#include "sse/tracer.h"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace twinray::cli {

// The tracers built in; beside them "plugin:PATH" names a tracer behind the tracer ABI (docs/plugins.md).
const std::vector<std::string>& tracer_names();
bool is_plugin(const std::string& tracer_name);
std::string tracer_description(const std::string& name);
// Empty when the tracer can run on this machine, else why not (the SSE tracer needs SSE4.1).
std::string tracer_unavailable_reason(const std::string& name);
inline const char* default_tracer = "sse";
// `precision` applies to the SSE tracer only; knobs asked of another tracer are refused
// (std::invalid_argument), as are knob combinations the SSE tracer is not built for. options.accel applies to
// every tracer. A plug-in throws plugin::UnsupportedKind, plugin::PluginUnusable or plugin::PluginFault.
RenderResult render_with(const std::string& tracer_name, const scene::Scene& scene, const RenderOptions& options,
                         const sse::Precision& precision = {});

// --tracer NAME or plugin:PATH.
void add_tracer_option(CLI::App& command, std::string& tracer);

// --fast-rcp, --fast-rsqrt, --dpps, --textbook-quadratic, --ftz and the preset --precision exact|fast.
void add_precision_options(CLI::App& command, sse::Precision& precision);
// Empty when `precision` can be used with the tracer, else why not (for a usage error).
std::string precision_problem(const std::string& tracer_name, const sse::Precision& precision);

// --accel auto|none|bvh (Accel names the choice for every tracer).
void add_accel_option(CLI::App& command, Accel& accel);

}  // namespace twinray::cli
