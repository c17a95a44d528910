// The tracers a user can pick with --tracer, by name.
#pragma once

#include "render/render.h"
#include "scene/scene.h"

#include <string>
#include <vector>

namespace twinray::cli {

const std::vector<std::string>& tracer_names();
std::string tracer_description(const std::string& name);
// Empty when the tracer can run on this machine, else why not (the SSE tracer needs SSE4.1).
std::string tracer_unavailable_reason(const std::string& name);
inline const char* default_tracer = "sse";
RenderResult render_with(const std::string& tracer_name, const scene::Scene& scene, const RenderOptions& options);

}  // namespace twinray::cli
