#include "pov/exporter.h"

#include <cstdio>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>

namespace twinray::pov {
namespace {

using scene::Vec3;

enum class Pass { shaded, object_ids };

// 17 significant digits: every double reads back as itself. Zero is printed without its sign.
std::string number(double value) {
    char text[40];
    std::snprintf(text, sizeof text, "%.17g", value == 0 ? 0.0 : value);
    return text;
}

std::string triple(double x, double y, double z) {
    return "<" + number(x) + ", " + number(y) + ", " + number(z) + ">";
}

// A point or direction of our right-handed world in POV-Ray's left-handed one: z is negated.
std::string point(const Vec3& v) { return triple(v[0], v[1], -v[2]); }

std::string colour(const Vec3& c) { return triple(c[0], c[1], c[2]); }

const char* csg_keyword(scene::CsgOp op) {
    switch (op) {
        // merge, not union: a union of ours is one solid without inner surfaces, which matters for the
        // rays that travel inside a transparent union.
        case scene::CsgOp::union_: return "merge";
        case scene::CsgOp::intersection: return "intersection";
        case scene::CsgOp::difference: return "difference";
    }
    throw std::logic_error("unknown CSG operation");
}

class Writer {
public:
    Writer(const scene::Scene& scene, Pass pass) : scene_(scene), pass_(pass) {}

    std::string write(int width, int height) {
        header(width, height);
        for (const scene::Object& object : scene_.objects) {
            this->object(object, 0);
        }
        return text_;
    }

private:
    void line(int indent, const std::string& text) {
        text_.append(static_cast<std::size_t>(indent) * 2, ' ');
        text_ += text;
        text_ += '\n';
    }

    void header(int width, int height) {
        const scene::Camera& camera = scene_.camera;
        bool shaded = pass_ == Pass::shaded;
        line(0, shaded ? "// twinray scene exported for POV-Ray 3.7 (docs/povray.md)."
                       : "// twinray object-id pass for POV-Ray 3.7: each primitive flat-coloured by its id (docs/povray.md).");
        line(0, "// Render: povray +I<this file> +O<out>.png +W" + std::to_string(width) + " +H" + std::to_string(height) +
                    " -D -A +FN8 File_Gamma=1.0");
        line(0, "// Right-handed world with y up converted to POV-Ray's left-handed one by negating every z.");
        line(0, "#version 3.7;");
        line(0, "");
        // adc_bailout 0: the default (1/255) drops faint secondary rays, which our model keeps.
        line(0, "global_settings {");
        line(1, "assumed_gamma 1.0");
        line(1, "ambient_light rgb " + (shaded ? colour(scene_.ambient_light) : triple(1, 1, 1)));
        line(1, "max_trace_level " + std::to_string(shaded ? scene_.max_depth : 1));
        line(1, "adc_bailout 0");
        line(0, "}");
        line(0, "");
        line(0, "background { color rgb " + (shaded ? colour(scene_.background) : triple(0, 0, 0)) + " }");
        line(0, "");
        // `right` is always explicit (POV-Ray's default is 1.33·x, not W/H). With |up| = 1 and
        // |right| = W/H, POV-Ray's direction length |right|/(2·tan(angle/2)) puts the image plane where
        // ours is and samples pixel centres as we do; `angle` is the horizontal field of view, like ours.
        line(0, "camera {");
        line(1, "perspective");
        line(1, "location " + point(camera.eye));
        line(1, "sky " + point(camera.up));
        line(1, "right " + triple(static_cast<double>(width) / static_cast<double>(height), 0, 0));
        line(1, "up " + triple(0, 1, 0));
        line(1, "angle " + number(camera.fov_deg));
        line(1, "look_at " + point(camera.look_at));
        line(0, "}");
        line(0, "");
        if (shaded) {
            // Point lights without fading; shadows on (`shadowless` is never set).
            for (const scene::Light& light : scene_.lights) {
                line(0, "light_source { " + point(light.position) + " color rgb " + colour(light.color) + " }");
            }
            line(0, "");
        }
    }

    void object(const scene::Object& object, int indent) {
        std::visit(
            [&](const auto& shape) {
                using S = std::decay_t<decltype(shape)>;
                if constexpr (std::is_same_v<S, scene::Csg>) {
                    line(indent, std::string(csg_keyword(shape.op)) + " {");
                    for (const scene::Object& child : shape.children) {
                        this->object(child, indent + 1);
                    }
                    line(indent, "}");
                } else {
                    line(indent, "// " + scene_.leaf_paths.at(static_cast<std::size_t>(object.leaf)));
                    line(indent, primitive(shape) + " {");
                    line(indent + 1, geometry(shape));
                    appearance(object, indent + 1);
                    line(indent, "}");
                }
            },
            object.shape);
    }

    static const char* primitive(const scene::Plane&) { return "plane"; }
    static const char* primitive(const scene::Sphere&) { return "sphere"; }
    // POV-Ray's cylinder is closed with flat caps unless `open` is given, as ours.
    static const char* primitive(const scene::Cylinder&) { return "cylinder"; }
    static const char* primitive(const scene::Box&) { return "box"; }

    // POV-Ray's plane {n, d} is n·p = d with the inside n·p < d, as ours.
    static std::string geometry(const scene::Plane& plane) { return point(plane.normal) + ", " + number(plane.offset); }
    static std::string geometry(const scene::Sphere& sphere) { return point(sphere.center) + ", " + number(sphere.radius); }
    static std::string geometry(const scene::Cylinder& cylinder) {
        return point(cylinder.base) + ", " + point(cylinder.cap) + ", " + number(cylinder.radius);
    }
    // Negating z swaps which corner has the smaller z.
    static std::string geometry(const scene::Box& box) {
        return triple(box.min[0], box.min[1], -box.max[2]) + ", " + triple(box.max[0], box.max[1], -box.min[2]);
    }

    void appearance(const scene::Object& leaf, int indent) {
        if (pass_ == Pass::object_ids) {
            int id = leaf.leaf + 1;
            if (id > 65535) {
                throw std::invalid_argument("the object-id pass encodes at most 65535 primitives");
            }
            // ambient 1 under white ambient light: the pixel is the pigment, id/255 per channel, which
            // an 8-bit PNG stores exactly.
            line(indent, "pigment { color rgb " + triple((id % 256) / 255.0, (id / 256) / 255.0, 0) + " }");
            line(indent, "finish { ambient 1 diffuse 0 }");
            return;
        }
        const scene::Material& m = scene_.materials.at(static_cast<std::size_t>(leaf.material));
        double t = m.transmission;
        // POV-Ray weighs a transparent surface's own ambient and diffuse by its opacity (1 − transmit);
        // dividing by it restores our formula. At transmission ≥ 1 nothing can: the terms are left out.
        double own = t == 0 ? 1.0 : (t < 1 ? 1.0 / (1.0 - t) : 0.0);
        if (t >= 1) {
            line(indent, "// transmission >= 1: POV-Ray cannot show this surface's ambient and diffuse terms");
        }
        line(indent, "// material " + scene_.material_names.at(static_cast<std::size_t>(leaf.material)));
        line(indent, "texture {");
        // rgbt: the transmitted ray and light through shadows are weighed by t, uncoloured, as ours.
        line(indent + 1, "pigment { color rgbt <" + number(m.color[0]) + ", " + number(m.color[1]) + ", " +
                             number(m.color[2]) + ", " + number(t) + "> }");
        line(indent + 1, "finish { ambient " + number(m.ambient * own) + " diffuse " + number(m.diffuse * own) + " phong " +
                             number(m.phong) + " phong_size " + number(m.phong_size) + " reflection " +
                             number(m.reflection) + " }");
        line(indent, "}");
        if (t > 0) {
            line(indent, "interior { ior " + number(m.ior) + " }");
        }
    }

    const scene::Scene& scene_;
    Pass pass_;
    std::string text_;
};

}  // namespace

std::string export_pov(const scene::Scene& scene, int width, int height) {
    return Writer(scene, Pass::shaded).write(width, height);
}

std::string export_pov_object_ids(const scene::Scene& scene, int width, int height) {
    return Writer(scene, Pass::object_ids).write(width, height);
}

}  // namespace twinray::pov
