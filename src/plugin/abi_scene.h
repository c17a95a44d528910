// The tracer ABI's flat scene (include/twinray/tracer.h) back in twinray's scene model: what a tracer written in
// C++ over twinray's own libraries builds from (src/peers/sse_tracer.cpp, twinray's SSE tracer as a plug-in).
#pragma once

#include "scene/scene.h"
#include "twinray/tracer.h"

#include <cstdint>
#include <stdexcept>
#include <vector>

namespace twinray::plugin {

// An ABI scene that breaks the header's contract: an index out of range, an object named twice, a number that is
// not finite, a singular transform. The message names the array and the element.
class InvalidAbiScene : public std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

struct AbiScene {
    // Every primitive a leaf, numbered by increasing `object` (so that ties still go to the smaller object);
    // scene.objects and scene.meshes in leaf order, each of default material; the camera at the scene's eye.
    scene::Scene scene;
    std::vector<std::uint32_t> object_of_leaf;
    std::vector<std::uint32_t> instance_of_leaf;  // its index in the ABI's instances, or TWINRAY_NONE
};

// Throws InvalidAbiScene.
AbiScene scene_from_abi(const twinray_scene& abi);

}  // namespace twinray::plugin
