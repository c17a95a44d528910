// The tracers a user can pick with --tracer, by name.
#pragma once

#include "plugin/plugin.h"
#include "render/render.h"
#include "scene/scene.h"
#include "sse/tracer.h"
#include "tracing/any_tracer.h"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace twinray::cli {

// The tracers by name (tracing/any_tracer.h): "reference", "reference-float", "sse" or "plugin:PATH".
using tracing::is_plugin;
using tracing::precision_problem;
using tracing::tracer_names;
using tracing::tracer_unavailable_reason;
inline const char* default_tracer = "sse";
// The tracer's image (tracing::make_tracer, then render): its errors are make_tracer's.
RenderResult render_with(const std::string& tracer_name, const scene::Scene& scene, const RenderOptions& options,
                         const sse::Precision& precision = {});
// The same for a caller that reads none of the objects, meshes and leaf paths of `scene` again: the SSE tracer empties
// them once it has compiled them (sse::Tracer::give_up_geometry). `accel_choice`, if given, receives what the SSE
// tracer's --accel auto chose and why ("bvh: the bounded objects weigh 47.6 sphere tests, above 24 ..."); empty for
// other tracers and accels.
RenderResult render_giving_up_geometry(const std::string& tracer_name, scene::Scene& scene,
                                       const RenderOptions& options, const sse::Precision& precision,
                                       std::string* accel_choice = nullptr);

// The exit status of a plug-in's error (README): a kind it lacks, unusable, a broken contract.
int plugin_exit_status(const plugin::PluginError& error);

// --tracer NAME or plugin:PATH.
void add_tracer_option(CLI::App& command, std::string& tracer);
// --tracer plugin:PATH, repeatable: the plug-ins a command runs beside twinray's own tracers (bench).
void add_plugin_option(CLI::App& command, std::vector<std::string>& plugins);

// --fast-rcp, --fast-rsqrt, --dpps, --textbook-quadratic, --ftz and the preset --precision exact|fast.
void add_precision_options(CLI::App& command, sse::Precision& precision);
// --accel auto|none|bvh (Accel names the choice for every tracer).
void add_accel_option(CLI::App& command, Accel& accel);

}  // namespace twinray::cli
