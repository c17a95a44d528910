// The tracers a user can pick with --tracer, by name.
#pragma once

#include "render/render.h"
#include "scene/scene.h"

#include <string>
#include <vector>

namespace twinray::cli {

const std::vector<std::string>& tracer_names();
std::string tracer_description(const std::string& name);
RenderResult render_with(const std::string& tracer_name, const scene::Scene& scene, const RenderOptions& options);

}  // namespace twinray::cli
