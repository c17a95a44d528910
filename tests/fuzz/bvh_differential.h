// The BVH differential check: bytes decoded into a small scene (JSON text, read by parse_scene, so the
// loader's contract holds) and rays, then every tracer asked the same questions with and without its BVH.
// Shared by the fuzz target (bvh_differential_fuzz.cpp) and the replay of its seeds and regressions
// (tests/fuzz_regression_test.cpp), so both run the very same check.
#pragma once

#include "../scene_json.h"
#include "reference/tracer.h"
#include "render/render.h"
#include "scene/loader.h"
#include "sse/cpu.h"
#include "sse/tracer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

namespace twinray::fuzz {

// Bytes read from the front; past the end every byte is 0, so any input decodes to something.
class ByteReader {
public:
    ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

    bool empty() const { return position_ >= size_; }
    int byte() { return empty() ? 0 : data_[position_++]; }

    // Mostly small integers, so that primitives coincide, touch and overlap; else fractions scaled by
    // 1e-6 to 1e6; else anything from 1e-300 to 1e300.
    double coordinate() {
        int mode = byte() % 8;
        if (mode < 4) {
            return byte() % 9 - 4;
        }
        double fraction = (byte() - 128) / 64.0;
        return fraction * scale(mode);
    }
    // Positive: quarters up to 4, else the same ranges as coordinate().
    double length() {
        int mode = byte() % 8;
        if (mode < 4) {
            return 0.25 * (1 + byte() % 16);
        }
        double fraction = (1 + byte()) / 64.0;
        return fraction * scale(mode);
    }
    scene::Vec3 point() {
        double x = coordinate(), y = coordinate();
        return {x, y, coordinate()};
    }

private:
    double scale(int mode) {
        if (mode < 6) {
            return 1;
        }
        return std::pow(10.0, mode == 6 ? byte() % 13 - 6 : byte() % 61 * 10 - 300);
    }

    const std::uint8_t* data_;
    std::size_t size_;
    std::size_t position_ = 0;
};

struct DifferentialCase {
    std::string scene_text;
    std::vector<std::pair<Vec3d, Vec3d>> rays;  // origin, unit direction
    // The SSE tracer's kernels: 0 exact, 1 rcp+ftz, 2 rsqrt+ftz. Not the textbook quadratic: its cancellation
    // can put a hit farther off its surface than any padding of the BVH's boxes (docs/sse-tracer.md, "The
    // BVH"), so the BVH promises its answers only for the knobs that keep hits within a few ulps.
    int fast_kernels = 0;
};

class CaseDecoder {
public:
    CaseDecoder(const std::uint8_t* data, std::size_t size) : in_(data, size) {}

    DifferentialCase decode() {
        DifferentialCase out;
        // One read per statement: the order in which operands of + are evaluated is unspecified, and the
        // fuzzer (clang) and the replay (GCC) must decode the same bytes into the same case.
        int first = in_.byte();
        out.fast_kernels = first % 4 % 3;
        // The high bit, clear in every input older than transforms, gives objects transforms: old inputs keep
        // decoding to the very cases they found.
        transforms_ = (first & 0x80) != 0;
        // Both high bits: some top-level meshes and CSG trees become shapes, placed by instances (and their copies).
        instances_ = (first & 0xC0) == 0xC0;
        int width = 4 + in_.byte() % 4;
        int height = 3 + in_.byte() % 3;
        scene::Vec3 eye = in_.point();
        scene::Vec3 look_at = in_.point();
        static const char* ups[] = {"[0, 1, 0]", "[1, 0, 0]", "[0, 0, 1]", "[1, 1, 1]"};
        const char* up = ups[in_.byte() % 4];
        int fov = 10 + in_.byte() % 160;
        int max_depth = 1 + in_.byte() % 3;
        std::string header = R"({"format": "twinray-scene/1", "image": {"width": )" + std::to_string(width) +
                             ", \"height\": " + std::to_string(height) +
                             "}, \"camera\": {\"eye\": " + test::json::vec3(eye) +
                             ", \"look_at\": " + test::json::vec3(look_at) + ", \"up\": " + up +
                             ", \"fov_deg\": " + std::to_string(fov) + "}, \"max_depth\": " + std::to_string(max_depth);
        header += R"(, "materials": {
          "matte": {"color": [0.8, 0.3, 0.2], "diffuse": 0.8, "phong": 0.3, "phong_size": 20},
          "mirror": {"color": [0.9, 0.9, 0.9], "diffuse": 0.2, "reflection": 0.6},
          "glass": {"color": [1, 1, 1], "diffuse": 0.05, "reflection": 0.1, "transmission": 0.8, "ior": 1.5},
          "clear": {"color": [1, 1, 1], "diffuse": 0, "transmission": 1, "ior": 1},
          "tinted": {"color": [0.3, 0.9, 0.4], "diffuse": 0.3, "reflection": 0.2, "transmission": 0.3, "ior": 1.2}})";
        header += ", \"lights\": [";
        for (int light = 0, lights = 1 + in_.byte() % 3; light < lights; ++light) {
            scene::Vec3 position = in_.point();
            header += (light == 0 ? "{\"position\": " : ", {\"position\": ") + test::json::vec3(position) +
                      ", \"color\": [0.7, 0.7, 0.7]}";
        }
        header += "]";
        // Rays first, so that a long list of objects cannot starve them of bytes; their targets are
        // resolved once the objects (and the points they stand at) are known.
        struct RaySpec {
            scene::Vec3 origin, free_target;
            int aim;
            double jitter;
        };
        std::vector<RaySpec> specs(static_cast<std::size_t>(in_.byte() % 17));
        for (RaySpec& spec : specs) {
            spec.origin = in_.point();
            spec.aim = in_.byte();
            spec.free_target = in_.point();
            spec.jitter = in_.byte() % 4 == 0 ? 0.0 : 1e-3 * in_.byte();
        }
        std::string objects;
        std::string previous;
        int previous_primitives = 0;
        int primitives_left = max_primitives;
        int count = in_.byte();
        count = 1 + (count | in_.byte() << 8) % max_primitives;
        for (; count > 0 && !in_.empty() && primitives_left > 0; --count) {
            // A copy of the previous object: exact coincidences, and piles of CSG objects.
            bool copy = in_.byte() % 6 == 0 && !previous.empty() && previous_primitives <= primitives_left;
            if (!copy) {
                // At most 64 primitives per CSG object (the loader's rule 20).
                int budget = std::min(scene::max_csg_leaves, primitives_left);
                int leaves_left = budget;
                previous = object(1, leaves_left, material(true));
                previous_primitives = budget - leaves_left;
            }
            primitives_left -= previous_primitives;
            objects += (objects.empty() ? "" : ", ") + previous;
        }
        out.scene_text =
            header + (shapes_.empty() ? "" : ", \"shapes\": {" + shapes_ + "}") + ", \"objects\": [" + objects + "]}";
        for (const RaySpec& spec : specs) {
            scene::Vec3 target = spec.free_target;
            if (spec.aim < 192 && !anchors_.empty()) {
                const scene::Vec3& anchor = anchors_[static_cast<std::size_t>(spec.aim) % anchors_.size()];
                target = anchor + scene::Vec3{spec.jitter, 0.5 * spec.jitter, -spec.jitter};
            }
            scene::Vec3 direction = target - spec.origin;
            double length = std::sqrt(math::dot(direction, direction));
            if (length > 0 && std::isfinite(length)) {
                out.rays.emplace_back(spec.origin, (1.0 / length) * direction);
            }
        }
        return out;
    }

private:
    // A few hundred at most: each input runs four tracers with and without their BVH under ASan, brute force
    // included, and must take well under the fuzzer's 10 s.
    static constexpr int max_primitives = 300;

    std::string material(bool named) {
        static const char* names[] = {"matte", "mirror", "glass", "clear", "tinted"};
        int choice = in_.byte() % 6;
        return choice == 5 && !named ? "" : names[choice % 5];
    }

    // At most `leaves_left` primitives and 4 levels; with transforms on, sometimes placed by one (about the first
    // point the object stands at, which rays aim at): a primitive's kind keeps some, the rest stay in object space.
    std::string object(int level, int& leaves_left, const std::string& own_material) {
        std::size_t first_anchor = anchors_.size();
        std::string text = untransformed_object(level, leaves_left, own_material);
        if (instances_ && level == 1 && holds_several_primitives(text) && in_.byte() % 2 == 0) {
            const std::string name = "s" + std::to_string(shape_count_++);
            shapes_ += (shapes_.empty() ? "\"" : ", \"") + name + "\": " + text;
            return R"({"type": "instance", "shape": ")" + name + "\"" + transform_about(anchors_[first_anchor]) + "}";
        }
        if (transforms_ && anchors_.size() > first_anchor && in_.byte() % 8 < 3) {
            text.insert(text.size() - 1, transform_about(anchors_[first_anchor]));
        }
        return text;
    }

    // A mesh or a CSG tree: the objects that an instance places as one leaf, its shape read once.
    static bool holds_several_primitives(const std::string& text) {
        for (const char* type : {"mesh", "union", "intersection", "difference"}) {
            if (text.rfind(std::string(R"({"type": ")") + type + "\"", 0) == 0) {
                return true;
            }
        }
        return false;
    }

    // Moved to the origin, scaled unevenly (factors 1/4 to 4, a quarter of them mirrored) or turned about any
    // axis or both, and moved back.
    std::string transform_about(const scene::Vec3& at) {
        int kind = in_.byte() % 3;
        std::string steps = "{\"translate\": " + test::json::vec3(-1.0 * at) + "}";
        if (kind != 1) {
            scene::Vec3 factors;
            for (int axis = 0; axis < 3; ++axis) {
                int code = in_.byte();
                factors[axis] = (code % 4 == 0 ? -0.25 : 0.25) * (1 + code / 4 % 16);
            }
            steps += ", {\"scale\": " + test::json::vec3(factors) + "}";
        }
        if (kind != 0) {
            scene::Vec3 axis = in_.point();
            if (axis == scene::Vec3{}) {
                axis = {0, 1, 0};
            }
            double degrees = in_.byte() % 2 == 0 ? 90.0 * (in_.byte() % 4) : in_.byte() * (360.0 / 256);
            steps += ", {\"rotate\": {\"axis\": " + test::json::vec3(axis) +
                     ", \"deg\": " + test::json::number(degrees) + "}}";
        }
        return ", \"transform\": [" + steps + ", {\"translate\": " + test::json::vec3(at) + "}]";
    }

    std::string untransformed_object(int level, int& leaves_left, const std::string& own_material) {
        int kind = in_.byte() % 10;
        if (kind >= 8 && level < 4 && leaves_left >= 2) {
            static const char* ops[] = {"union", "intersection", "difference"};
            const char* op = ops[in_.byte() % 3];
            std::vector<std::string> children;
            int child_count = 2 + in_.byte() % 3;
            for (int child = 0; child < child_count && leaves_left > 0; ++child) {
                children.push_back(object(level + 1, leaves_left, material(false)));
            }
            if (children.size() >= 2) {
                return test::json::csg(op, children, own_material);
            }
            return children.front();
        }
        if (kind == 7 && level == 1 && leaves_left >= 2) {
            return mesh(leaves_left, own_material);
        }
        --leaves_left;
        scene::Vec3 at = in_.point();
        anchors_.push_back(at);
        if (kind == 0) {
            static const scene::Vec3 axes[] = {{0, 1, 0}, {0, -1, 0}, {1, 0, 0}, {0, 0, -1}};
            int choice = in_.byte() % 5;
            return test::json::plane(choice < 4 ? axes[choice] : at, in_.coordinate(), own_material);
        }
        if (kind <= 3) {
            return test::json::sphere(at, in_.length(), own_material);
        }
        if (kind <= 5) {
            double x = in_.length(), y = in_.length();
            return test::json::box(at, at + scene::Vec3{x, y, in_.length()}, own_material);
        }
        scene::Vec3 axis = in_.point();
        if (axis == scene::Vec3{}) {
            axis = {0, in_.length(), 0};
        }
        return test::json::cylinder(at, at + axis, in_.length(), own_material);
    }

    // A fan of 2 to 9 triangles sharing their centre and spokes (closed when its rim comes back), its
    // vertices and the spokes' midpoints anchors for rays: ties on shared edges and vertices, and a mesh's
    // triangles in the BVH among other primitives.
    std::string mesh(int& leaves_left, const std::string& own_material) {
        int triangles = std::min(leaves_left, 2 + in_.byte() % 8);
        bool closed = in_.byte() % 2 == 0 && triangles >= 3;
        int rim = closed ? triangles : triangles + 1;
        std::vector<scene::Vec3> vertices{in_.point()};
        for (int i = 0; i < rim; ++i) {
            vertices.push_back(in_.point());
        }
        std::vector<std::array<int, 3>> faces;
        for (int i = 0; i < triangles; ++i) {
            faces.push_back({0, 1 + i, 1 + (i + 1) % rim});
        }
        leaves_left -= triangles;
        for (std::size_t i = 0; i < vertices.size(); ++i) {
            anchors_.push_back(vertices[i]);
            anchors_.push_back(0.5 * (vertices[0] + vertices[i]));
        }
        std::string text = R"({"type": "mesh", "vertices": [)";
        for (std::size_t i = 0; i < vertices.size(); ++i) {
            text += (i == 0 ? "" : ", ") + test::json::vec3(vertices[i]);
        }
        text += R"(], "triangles": [)";
        for (std::size_t i = 0; i < faces.size(); ++i) {
            text += (i == 0 ? "[" : ", [") + std::to_string(faces[i][0]) + ", " + std::to_string(faces[i][1]) + ", " +
                    std::to_string(faces[i][2]) + "]";
        }
        return text + "]" + test::json::material_key(own_material) + "}";
    }

    ByteReader in_;
    bool transforms_ = false;
    bool instances_ = false;
    std::string shapes_;  // the "shapes" block's members
    int shape_count_ = 0;
    std::vector<scene::Vec3> anchors_;  // a point of each primitive, for rays to aim at
};

// Collects the first answer that differs between brute force and the BVH, described for a human. The
// description is written only then: building it for every comparison would cost more than the tracing.
class Differences {
public:
    // What the following comparisons are about: `tracer`'s answer for ray `index` of the case, or its image.
    void about(const char* tracer, const std::pair<Vec3d, Vec3d>* ray, std::size_t index) {
        tracer_ = tracer;
        ray_ = ray;
        index_ = index;
    }
    template <typename V>
    void bits(const V& brute, const V& bvh, const char* what) {
        if (first_.empty() && std::memcmp(&brute, &bvh, sizeof(V)) != 0) {
            first_ = place() + ": " + what + " differs";
        }
    }
    void equal(long long brute, long long bvh, const char* what) {
        if (first_.empty() && brute != bvh) {
            first_ = place() + ": " + what + " differs: " + std::to_string(brute) + " without the BVH, " +
                     std::to_string(bvh) + " with it";
        }
    }
    const std::string& first() const { return first_; }

private:
    std::string place() const {
        if (ray_ == nullptr) {
            return std::string(tracer_) + ", image, pixel " + std::to_string(index_);
        }
        return std::string(tracer_) + ", ray " + std::to_string(index_) + " (origin " + test::json::vec3(ray_->first) +
               ", direction " + test::json::vec3(ray_->second) + ")";
    }

    std::string first_;
    const char* tracer_ = "";
    const std::pair<Vec3d, Vec3d>* ray_ = nullptr;
    std::size_t index_ = 0;
};

template <typename Hit>
void compare_hits(const std::optional<Hit>& brute, const std::optional<Hit>& bvh, Differences& out) {
    out.equal(brute.has_value(), bvh.has_value(), "hit or miss");
    if (brute && bvh) {
        out.equal(brute->leaf, bvh->leaf, "object hit (leaf)");
        out.equal(brute->triangle, bvh->triangle, "triangle hit");
        out.equal(brute->part, bvh->part, "part of a solid shape hit");
        out.bits(brute->t, bvh->t, "t");
        out.bits(brute->normal, bvh->normal, "normal");
        out.bits(brute->point, bvh->point, "point");
        out.equal(brute->entering, bvh->entering, "entering");
        out.bits(brute->spawn_offset, bvh->spawn_offset, "spawn offset");
    }
}

inline void compare_renders(const RenderResult& brute, const RenderResult& bvh, const char* tracer, Differences& out) {
    const std::vector<Rgb>& a = brute.image.pixels();
    const std::vector<Rgb>& b = bvh.image.pixels();
    for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
        out.about(tracer, nullptr, i);
        out.bits(a[i], b[i], "colour");
    }
    out.equal(static_cast<long long>(brute.tally.rays), static_cast<long long>(bvh.tally.rays), "rays traced");
}

template <typename T>
void compare_reference(const scene::Scene& scene, const DifferentialCase& input, const char* tracer, Differences& out) {
    reference::Tracer<T> brute(scene, Accel::none);
    reference::Tracer<T> bvh(scene, Accel::bvh);
    for (std::size_t i = 0; i < input.rays.size(); ++i) {
        reference::Ray<T> ray{reference::Vec3<T>(input.rays[i].first), reference::Vec3<T>(input.rays[i].second)};
        out.about(tracer, &input.rays[i], i);
        compare_hits(brute.intersect(ray), bvh.intersect(ray), out);
        out.bits(brute.trace(ray, 1), bvh.trace(ray, 1), "colour");
    }
}

// Empty when every answer is the same bit for bit, or when the loader refuses the scene; else the first
// difference: which tracer, which ray or pixel, what differs.
inline std::string first_difference(const DifferentialCase& input) {
    std::optional<scene::Scene> scene;
    try {
        scene = scene::parse_scene(input.scene_text, "<bvh_differential>");
    } catch (const scene::SceneError&) {
        return "";
    }
    Differences out;
    RenderOptions options;
    options.threads = 1;
    if (sse::cpu_supports_sse41()) {
        sse::Precision precision;
        precision.fast_rcp = input.fast_kernels == 1;
        precision.fast_rsqrt = input.fast_kernels == 2;
        precision.flush_denormals = input.fast_kernels != 0;
        sse::Tracer brute(*scene, precision, Accel::none);
        sse::Tracer bvh(*scene, precision, Accel::bvh);
        for (std::size_t i = 0; i < input.rays.size(); ++i) {
            sse::Ray ray{input.rays[i].first, sse::Vec3(input.rays[i].second)};
            out.about("sse", &input.rays[i], i);
            compare_hits(brute.intersect(ray), bvh.intersect(ray), out);
            TraceTally brute_tally, bvh_tally;
            out.bits(brute.trace(ray, 1, &brute_tally), bvh.trace(ray, 1, &bvh_tally), "colour");
            out.equal(static_cast<long long>(brute_tally.rays), static_cast<long long>(bvh_tally.rays), "rays traced");
        }
        options.accel = Accel::none;
        RenderResult brute_image = sse::render(*scene, options, precision);
        options.accel = Accel::bvh;
        compare_renders(brute_image, sse::render(*scene, options, precision), "sse", out);
    }
    compare_reference<double>(*scene, input, "reference<double>", out);
    compare_reference<float>(*scene, input, "reference<float>", out);
    options.accel = Accel::none;
    RenderResult brute_image = reference::render<double>(*scene, options);
    options.accel = Accel::bvh;
    compare_renders(brute_image, reference::render<double>(*scene, options), "reference<double>", out);
    return out.first();
}

}  // namespace twinray::fuzz
