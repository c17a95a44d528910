// Objects of a twinray-scene/1 file written as JSON text, for tests and fuzz targets that build scenes
// through the loader (parse_scene) rather than in code, so that the loader's contract holds for them.
// Numbers are written with 17 significant digits: the loader reads back the very doubles given.
#pragma once

#include "scene/scene.h"

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace twinray::test::json {

inline std::string number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", value);
    return text;
}

inline std::string vec3(const scene::Vec3& v) {
    return "[" + number(v[0]) + ", " + number(v[1]) + ", " + number(v[2]) + "]";
}

// `material` empty: none named (the CSG parent's, else the default).
inline std::string material_key(std::string_view material) {
    return material.empty() ? std::string() : ", \"material\": \"" + std::string(material) + "\"";
}

inline std::string plane(const scene::Vec3& normal, double offset, std::string_view material) {
    return R"({"type": "plane", "normal": )" + vec3(normal) + ", \"offset\": " + number(offset) +
           material_key(material) + "}";
}

inline std::string sphere(const scene::Vec3& center, double radius, std::string_view material) {
    return R"({"type": "sphere", "center": )" + vec3(center) + ", \"radius\": " + number(radius) +
           material_key(material) + "}";
}

inline std::string box(const scene::Vec3& min, const scene::Vec3& max, std::string_view material) {
    return R"({"type": "box", "min": )" + vec3(min) + ", \"max\": " + vec3(max) + material_key(material) + "}";
}

inline std::string cylinder(const scene::Vec3& base, const scene::Vec3& cap, double radius, std::string_view material) {
    return R"({"type": "cylinder", "base": )" + vec3(base) + ", \"cap\": " + vec3(cap) +
           ", \"radius\": " + number(radius) + material_key(material) + "}";
}

// A scene file's opening, up to its shapes or objects: width × height pixels seen from `eye` towards (0, 0.5, −1), a
// glass, a red and a blue material, and two lights. What the instance suites place their objects in.
inline std::string lit_scene_opening(int width, int height, const scene::Vec3& eye) {
    return R"({
  "format": "twinray-scene/1",
  "image": { "width": )" +
           std::to_string(width) + R"(, "height": )" + std::to_string(height) + R"( },
  "camera": { "eye": )" +
           vec3(eye) + R"(, "look_at": [0, 0.5, -1] },
  "materials": {
    "glass": { "color": [1, 1, 1], "diffuse": 0.1, "reflection": 0.1, "transmission": 0.8, "ior": 1.5 },
    "red": { "color": [0.9, 0.2, 0.1], "diffuse": 0.7, "phong": 0.4 },
    "blue": { "color": [0.2, 0.3, 0.9], "diffuse": 0.7, "reflection": 0.3 }
  },
  "lights": [ { "position": [-3, 6, 4] }, { "position": [4, 3, 2], "color": [0.4, 0.4, 0.5] } ],
)";
}

// `op`: "union", "intersection" or "difference".
inline std::string csg(std::string_view op, const std::vector<std::string>& children, std::string_view material) {
    std::string text = "{\"type\": \"" + std::string(op) + "\"" + material_key(material) + ", \"children\": [";
    for (std::size_t i = 0; i < children.size(); ++i) {
        text += (i == 0 ? "" : ", ") + children[i];
    }
    return text + "]}";
}

}  // namespace twinray::test::json
