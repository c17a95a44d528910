// A scene of `twinray generate` built in memory, as the command would write it (cli/generate_scene.h): the
// large scenes the BVH tests and the conformance suite's sampling run on.
#pragma once

#include "cli/generate_scene.h"
#include "scene/loader.h"

#include <string>

namespace twinray::test {

inline scene::Scene generated_scene(const std::string& family, int size) {
    std::string text;
    cli::generate_scene(family, size, 1, {[&](std::string_view piece) { text.append(piece); }, {}});
    return scene::parse_scene(text, family);
}

}  // namespace twinray::test
