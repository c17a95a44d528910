// How the loader's parts refuse a scene: a Refusal names the JSON path (or line and column) and what is
// wrong; parse_scene adds the source name. Shared wording helpers for the messages.
#pragma once

#include "scene/scene.h"

#include <charconv>
#include <iterator>
#include <string>
#include <string_view>

namespace twinray::scene {

struct Refusal {
    std::string location;
    std::string problem;
};

[[noreturn]] inline void refuse(const std::string& path, std::string problem) {
    throw Refusal{path.empty() ? "(root)" : path, std::move(problem)};
}

inline std::string key_path(const std::string& parent, std::string_view key) {
    return parent.empty() ? std::string(key) : parent + "." + std::string(key);
}

inline std::string index_path(const std::string& parent, std::size_t index) {
    return parent + "[" + std::to_string(index) + "]";
}

inline std::string format_number(double value) {
    char digits[32];  // the shortest round-trip form of any double fits in 24
    return std::string(digits, std::to_chars(std::begin(digits), std::end(digits), value).ptr);
}

// A string as JSON writes it, quoted and escaped.
std::string in_quotes(std::string_view text);

// Why a scene is refused at `what` ("primitive number 5 of the scene"): past `limit` primitives.
inline std::string over_primitive_limit(const std::string& what, std::size_t limit) {
    return what + ": more than the limit of " + std::to_string(limit) + " primitives (about " +
           std::to_string(bytes_per_primitive) + " bytes of memory each when rendered; no scene may hold more than " +
           std::to_string(max_scene_primitives) + ")";
}

// The deepest nesting of arrays and objects a scene may use: far beyond any real scene, and low enough
// that nothing recursing over the tree can exhaust the stack.
constexpr std::size_t max_json_depth = 200;

}  // namespace twinray::scene
