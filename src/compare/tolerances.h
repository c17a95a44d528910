// Per-scene thresholds, stated once in a manifest (tests/tolerances.json) and read by the conformance
// tests, the golden tests and `twinray diff`, so that every judge applies the same numbers.
#pragma once

#include "compare/image_compare.h"

#include <filesystem>
#include <map>
#include <string>

namespace twinray::compare {

struct SceneTolerances {
    Thresholds sse;     // the SSE tracer's image against the reference's (both clamped to [0, 1])
    Thresholds golden;  // the reference's 8-bit image against its stored golden image
    std::string why;    // the stated reason for any departure from the defaults
};

class ToleranceManifest {
public:
    // Throws std::runtime_error naming the file and the JSON path of a bad entry.
    static ToleranceManifest load(const std::filesystem::path& file);
    // Built-in defaults, for when no manifest is given or found.
    static ToleranceManifest defaults();

    // The scene's own entry over the defaults; `scene_name` is the file's stem ("showcase").
    SceneTolerances for_scene(const std::string& scene_name) const;

private:
    SceneTolerances defaults_;
    std::map<std::string, SceneTolerances> scenes_;
};

}  // namespace twinray::compare
