// The POV-Ray 3.7 exporter: a scene of ours as a .pov file that makes POV-Ray compute the shading model
// of docs/scene-format.md, so that a mature tracer nobody here wrote can judge ours (docs/povray.md says how each
// setting is chosen and which residual differences remain).
#pragma once

#include "scene/scene.h"

#include <string>

namespace twinray::pov {

// The scene rendered at width × height (the caller resolves command-line sizes): camera, lights,
// primitives, CSG and materials. POV-Ray's world is left-handed, so every z is negated; the image is not
// mirrored. Numbers are printed with 17 significant digits, so they read back exactly. Render it with
// -A (one ray per pixel) and File_Gamma=1.0 (docs/povray.md).
std::string export_pov(const scene::Scene& scene, int width, int height);

// The same camera and geometry with every primitive flat-coloured by its id, for comparing which
// primitive each pixel's primary ray meets: a pixel of the 8-bit render reads (id mod 256, id / 256, 0)
// with id = leaf + 1 (Scene::leaf_paths), and 0 where the ray meets nothing. No lights, no reflection
// or refraction, transparency off. Throws std::invalid_argument beyond 65535 primitives.
std::string export_pov_object_ids(const scene::Scene& scene, int width, int height);

// The id a pixel of export_pov_object_ids's render encodes, from its 8-bit red and green.
inline int decode_object_id(int red, int green) {
    return red + 256 * green;
}

}  // namespace twinray::pov
