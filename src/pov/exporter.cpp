#include "pov/exporter.h"

#include "scene/depth_control.h"
#include "scene/geometry.h"
#include "scene/refusal.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace twinray::pov {
namespace {

using scene::Vec3;

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
std::string point(const Vec3& v) {
    return triple(v[0], v[1], -v[2]);
}

std::string colour(const Vec3& c) {
    return triple(c[0], c[1], c[2]);
}

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

// How one of our materials is written for POV-Ray (docs/povray.md, "Materials").
//
// POV-Ray's transparent surface (pigment transmit f, finish `refraction` k, which POV-Ray 3.7 still
// reads though it calls it obsolete) shows
//     (1 − f)·(ambient and diffuse terms) + phong + reflection·I(reflected) + k·f·I(refracted),
// but on total internal reflection k·I(internally reflected) and no `reflection` term; a shadow ray
// crossing it keeps f of the light. Ours shows ambient + diffuse + phong + r·I(reflected) + t·I(refracted),
// on total internal reflection (r + t)·I(reflected), and a shadow ray keeps t. So k = r + t and
// f = t/(r + t) give our refraction and total internal reflection, ambient and diffuse divided by
// (1 − f) give our own terms, and when f ≠ t a second, invisible copy of the object with transmit t
// casts the shadows (see Writer::top_level).
struct PovMaterial {
    double transmit = 0;
    double refraction = 1;  // k
    double own_scale = 1;   // on ambient and diffuse
    std::string residual;   // what POV-Ray cannot express, if anything
};

PovMaterial map_material(const scene::Material& m) {
    const double t = m.transmission;
    const double r = m.reflection;
    PovMaterial p;
    if (t == 0) {
        return p;
    }
    bool has_own_terms = m.ambient != 0 || m.diffuse != 0;
    if (r > 0 || t >= 1 || !has_own_terms) {
        p.refraction = r + t;
        p.transmit = t / p.refraction;
    } else {
        // k = t would need f = 1, which hides the surface's own ambient and diffuse entirely; keeping
        // them costs the weight of internally reflected rays instead (1 where ours is t).
        p.transmit = t;
        p.residual =
            "reflection 0 with 0 < transmission < 1: POV-Ray weighs total internal reflection by 1, ours by "
            "transmission";
    }
    if (p.transmit < 1) {
        p.own_scale = 1 / (1 - p.transmit);
    } else {
        p.own_scale = 0;
        if (has_own_terms) {
            p.residual =
                "transmission >= 1 with reflection 0: POV-Ray cannot show this surface's ambient and diffuse terms";
        }
    }
    return p;
}

enum class Pass {
    shaded,         // what the camera, reflected and refracted rays see
    shadow_caster,  // an invisible copy that casts the shadows, when the shaded copy's transmit is not ours
    object_ids,     // every primitive flat-coloured by its id
};

// How one top-level object's primitives share POV-Ray's `interior`.
//
// POV-Ray tells entering from leaving, and so the ratio of indices, by the identity of the interior
// a ray meets: leaving through a surface with another interior than the one it entered counts as
// entering a second solid. Ours decides by the composite solid and takes the ior of the surface hit.
// So when the transparent primitives of a top-level object agree on ior and k, one interior is set on
// the object and every primitive inherits it (opaque ones never refract). POV-Ray copies each
// primitive's finish `refraction` into the interior it holds (1 when not given), so then every
// primitive of the object, opaque or not, carries the same k. When they disagree each transparent
// primitive keeps its own interior: a residual difference.
struct InteriorPlan {
    bool transparent = false;  // some primitive has transmission > 0
    bool shared = false;       // one interior for the whole object
    double ior = 1;
    double refraction = 1;
    bool needs_shadow_caster = false;
};

class Writer {
public:
    Writer(const scene::Scene& scene, bool object_ids) : scene_(scene), object_ids_(object_ids) {
        for (const scene::Material& material : scene.materials) {
            materials_.push_back(map_material(material));
        }
    }

    std::string write(int width, int height) {
        header(width, height);
        for (const scene::Object& object : scene_.objects) {
            top_level(object);
        }
        write_solid_instances();
        // Each mesh shape once; its instances name it (POV-Ray copies a declared mesh's reference, not its data).
        for (std::size_t i = 0; i < scene_.mesh_shapes.size(); ++i) {
            line(0, "// " + scene_.mesh_shapes[i].name);
            line(0, "#declare " + shape_identifier(i) + " = mesh2 {");
            mesh_geometry(*scene_.mesh_shapes[i].data);
            line(0, "}");
        }
        for (const scene::Mesh& mesh : scene_.meshes) {
            write_mesh(mesh);
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
        line(0,
             object_ids_
                 ? "// twinray object-id pass for POV-Ray 3.7: each primitive flat-coloured by its id (docs/povray.md)."
                 : "// twinray scene exported for POV-Ray 3.7 (docs/povray.md).");
        line(0, "// Render: povray +I<this file> +O<out>.png +W" + std::to_string(width) + " +H" +
                    std::to_string(height) + " -D -A +FN8 File_Gamma=1.0");
        line(0, "// Right-handed world with y up converted to POV-Ray's left-handed one by negating every z.");
        std::vector<bool> used(materials_.size(), false);
        for (const scene::Object& object : scene_.objects) {
            for_each_leaf(object,
                          [&](const scene::Object& leaf) { used.at(static_cast<std::size_t>(leaf.material)) = true; });
        }
        for (const scene::Mesh& mesh : scene_.meshes) {
            used.at(static_cast<std::size_t>(mesh.material)) = true;
        }
        for (const scene::SolidInstance& instance : scene_.solid_instances) {
            for_each_leaf(shape_of(instance).tree, [&](const scene::Object& part) {
                used.at(static_cast<std::size_t>(material_of(part, &instance))) = true;
            });
        }
        for (std::size_t i = 0; i < materials_.size() && !object_ids_; ++i) {
            if (used[i] && !materials_[i].residual.empty()) {
                line(0, "// Not exact: material " + scene_.material_names[i] + ": " + materials_[i].residual + ".");
            }
        }
        line(0, "#version 3.7;");
        line(0, "");
        // POV-Ray stops a ray whose weight is below adc_bailout, as our min_weight does; for the proven cutoff,
        // the weight below which no single ray can move a pixel (DepthControl::bailout_weight). Without it,
        // POV-Ray's default 1/255 would drop rays our model keeps.
        line(0, "global_settings {");
        line(1, "assumed_gamma 1.0");
        line(1, "ambient_light rgb " + (object_ids_ ? triple(1, 1, 1) : colour(scene_.ambient_light)));
        line(1, "max_trace_level " + std::to_string(object_ids_ ? 1 : scene_.max_depth));
        line(1, "adc_bailout " + number(object_ids_ ? 0.0 : scene::DepthControl(scene_).bailout_weight()));
        line(0, "}");
        line(0, "");
        line(0, "background { color rgb " + (object_ids_ ? triple(0, 0, 0) : colour(scene_.background)) + " }");
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
        if (!object_ids_) {
            // Point lights without fading; shadows on (`shadowless` is never set).
            for (const scene::Light& light : scene_.lights) {
                line(0, "light_source { " + point(light.position) + " color rgb " + colour(light.color) + " }");
            }
            line(0, "");
        }
    }

    template <class Visit>
    void for_each_leaf(const scene::Object& object, const Visit& visit) const {
        if (const auto* csg = std::get_if<scene::Csg>(&object.shape)) {
            for (const scene::Object& child : csg->children) {
                for_each_leaf(child, visit);
            }
        } else {
            visit(object);
        }
    }

    // A leaf's material; on an instance of a solid shape (`placed`), the part's as the instance resolves it.
    int material_of(const scene::Object& leaf, const scene::SolidInstance* placed) const {
        return placed == nullptr ? leaf.material : placed->material_of(shape_of(*placed), leaf.leaf);
    }

    InteriorPlan plan_interior(const scene::Object& object, const scene::SolidInstance* placed) const {
        InteriorPlan plan;
        plan.shared = true;
        for_each_leaf(object, [&](const scene::Object& leaf) {
            const auto material = static_cast<std::size_t>(material_of(leaf, placed));
            const scene::Material& m = scene_.materials[material];
            const PovMaterial& p = materials_[material];
            if (m.transmission == 0) {
                return;
            }
            if (!plan.transparent) {
                plan.ior = m.ior;
                plan.refraction = p.refraction;
            } else if (m.ior != plan.ior || p.refraction != plan.refraction) {
                plan.shared = false;
            }
            plan.transparent = true;
            plan.needs_shadow_caster = plan.needs_shadow_caster || p.transmit != m.transmission;
        });
        plan.shared = plan.shared && plan.transparent;
        return plan;
    }

    const scene::SolidShape& shape_of(const scene::SolidInstance& instance) const {
        return scene_.solid_shapes[static_cast<std::size_t>(instance.placement.shape)];
    }

    // Each solid shape declared once for each material its instances give it, since its parts' textures and shared
    // interior depend on that material; in the object-id pass once, untextured, each instance colouring it by its id
    // (POV-Ray gives an object's texture to the parts that have none). Each instance is an object of its declaration
    // under its matrix, with one of the shadow caster beside it where the declaration has one.
    void write_solid_instances() {
        std::map<std::pair<int, int>, bool> casts_by_copy;  // (shape, material) declared → it has a shadow caster
        for (const scene::SolidInstance& instance : scene_.solid_instances) {
            const int material = object_ids_ ? -1 : instance.material;
            const std::string identifier = "twinray_solid_" + std::to_string(instance.placement.shape) +
                                           (object_ids_ ? "" : "_" + std::to_string(material));
            auto [declared, first] = casts_by_copy.try_emplace({instance.placement.shape, material}, false);
            if (first) {
                line(0,
                     "// " + shape_of(instance).name +
                         (object_ids_ ? ""
                                      : ", material " + scene_.material_names.at(static_cast<std::size_t>(material)) +
                                            " where its parts name none"));
                declared->second = top_level(shape_of(instance).tree, &instance, identifier);
            }
            line(0, "// " + scene_.leaf_name(instance.leaf));
            const std::string placement = matrix(instance.placement.transform());
            line(0, "object {");
            line(1, identifier);
            if (object_ids_) {
                appearance(instance.leaf, instance.material, 1, Pass::object_ids);
            }
            line(1, placement);
            line(0, "}");
            if (declared->second) {
                line(0, "object { " + identifier + "_shadow " + placement + " }");
            }
        }
    }

    // An element of `objects`; or, with `placed`, the tree of its solid shape declared as `identifier` (and its
    // shadow caster as identifier_shadow), the parts coloured as `placed` colours them. Whether it has a shadow caster.
    bool top_level(const scene::Object& object, const scene::SolidInstance* placed = nullptr,
                   const std::string& identifier = "") {
        const auto declare = [&](const std::string& name) {
            if (placed != nullptr) {
                line(0, "#declare " + name + " =");
            }
        };
        std::vector<std::string> modifiers;
        if (object_ids_) {
            declare(identifier);
            write_object(object, 0, Pass::object_ids, modifiers, placed);
            return false;
        }
        plan_ = plan_interior(object, placed);
        if (plan_.shared) {
            modifiers.push_back("interior { ior " + number(plan_.ior) + " }");
        } else if (plan_.transparent) {
            modifiers.push_back(
                "// transparent primitives with different ior or k keep their own interiors: not exact "
                "(docs/povray.md)");
        }
        if (plan_.needs_shadow_caster) {
            modifiers.push_back("no_shadow  // the copy below casts this object's shadows");
        }
        declare(identifier);
        write_object(object, 0, Pass::shaded, modifiers, placed);
        if (plan_.needs_shadow_caster) {
            line(0, "// The same object, invisible to every ray but shadow rays, passing our transmission to shadows.");
            declare(identifier + "_shadow");
            write_object(object, 0, Pass::shadow_caster, {"no_image", "no_reflection"}, placed);
        }
        return plan_.needs_shadow_caster;
    }

    // `modifiers` close the object's block (POV-Ray wants object modifiers after a CSG's children). `placed`: an
    // instance whose solid shape's tree this is (its leaves are parts, named by their paths in the shape and
    // coloured as the instance colours them, or left untextured in the object-id pass).
    void write_object(const scene::Object& object, int indent, Pass pass,
                      const std::vector<std::string>& modifiers = {}, const scene::SolidInstance* placed = nullptr) {
        std::visit(
            [&](const auto& shape) {
                using S = std::decay_t<decltype(shape)>;
                if constexpr (!scene::is_primitive<S>) {
                    line(indent, std::string(csg_keyword(shape.op)) + " {");
                    for (const scene::Object& child : shape.children) {
                        write_object(child, indent + 1, pass, {}, placed);
                    }
                } else {
                    const auto leaf = static_cast<std::size_t>(object.leaf);
                    line(indent, "// " + (placed != nullptr ? shape_of(*placed).part_paths.at(leaf)
                                                            : scene_.leaf_paths.at(leaf)));
                    line(indent, std::string(primitive(shape)) + " {");
                    line(indent + 1, geometry(shape));
                    if (placed == nullptr || pass != Pass::object_ids) {
                        appearance(object.leaf, material_of(object, placed), indent + 1, pass);
                    }
                }
                for (const std::string& modifier : modifiers) {
                    line(indent + 1, modifier);
                }
                line(indent, "}");
            },
            object.shape);
    }

    // mesh2, its degenerate triangles left out (we never hit them; POV-Ray warns of them). With smooth
    // normals, normal_vectors as given (POV-Ray interpolates them itself, not turned to the geometric side).
    // Negating z mirrors each triangle, which only swaps its sides; POV-Ray does not cull either.
    void write_mesh(const scene::Mesh& mesh) {
        const scene::MeshData& data = *mesh.data;
        const auto material = static_cast<std::size_t>(mesh.material);
        const scene::Material& m = scene_.materials.at(material);
        plan_ = InteriorPlan{};
        if (!object_ids_ && m.transmission > 0) {
            plan_ = {true, true, m.ior, materials_.at(material).refraction,
                     materials_.at(material).transmit != m.transmission};
        }
        auto write = [&](Pass pass, const std::vector<std::string>& modifiers) {
            line(0, "// " + scene_.leaf_name(mesh.leaf));
            if (mesh.placement) {
                line(0, "object {");
                line(1, shape_identifier(static_cast<std::size_t>(mesh.placement->shape)));
            } else {
                line(0, "mesh2 {");
                mesh_geometry(data);
            }
            appearance(mesh.leaf, mesh.material, 1, pass);
            for (const std::string& modifier : modifiers) {
                line(1, modifier);
            }
            if (mesh.placement) {
                line(1, matrix(mesh.placement->transform()));
            }
            line(0, "}");
        };
        if (object_ids_) {
            write(Pass::object_ids, {});
            return;
        }
        std::vector<std::string> modifiers;
        if (plan_.shared) {
            modifiers.push_back("interior { ior " + number(plan_.ior) + " }");
        }
        if (plan_.needs_shadow_caster) {
            modifiers.push_back("no_shadow  // the copy below casts this mesh's shadows");
        }
        write(Pass::shaded, modifiers);
        if (plan_.needs_shadow_caster) {
            line(0, "// The same mesh, invisible to every ray but shadow rays, passing our transmission to shadows.");
            write(Pass::shadow_caster, {"no_image", "no_reflection"});
        }
    }

    static std::string shape_identifier(std::size_t shape) { return "twinray_shape_" + std::to_string(shape); }

    // A mesh2's vertices, normals where it shades smooth, and live triangles.
    void mesh_geometry(const scene::MeshData& data) {
        line(1, "vertex_vectors { " + std::to_string(data.vertices.size()) + ",");
        for (const scene::Vec3& vertex : data.vertices) {
            line(2, point(vertex) + ",");
        }
        line(1, "}");
        if (data.smooth) {
            line(1, "normal_vectors { " + std::to_string(data.normals.size()) + ",");
            for (const scene::Vec3& normal : data.normals) {
                line(2, point(normal) + ",");
            }
            line(1, "}");
        }
        line(1, "face_indices { " + std::to_string(data.triangles.size() - data.degenerate.size()) + ",");
        scene::for_each_live_triangle(data, [&](std::uint32_t i) {
            const std::array<std::uint32_t, 3>& t = data.triangles[i];
            line(2, "<" + std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " + std::to_string(t[2]) + ">,");
        });
        line(1, "}");
    }

    static const char* primitive(const scene::Plane&) { return "plane"; }
    static const char* primitive(const scene::Sphere&) { return "sphere"; }
    // POV-Ray's cylinder is closed with flat caps unless `open` is given, as ours.
    static const char* primitive(const scene::Cylinder&) { return "cylinder"; }
    static const char* primitive(const scene::Box&) { return "box"; }

    // POV-Ray's plane {n, d} is n·p = d with the inside n·p < d, as ours.
    static std::string geometry(const scene::Plane& plane) { return point(plane.normal) + ", " + number(plane.offset); }
    static std::string geometry(const scene::Sphere& sphere) {
        return point(sphere.center) + ", " + number(sphere.radius);
    }
    static std::string geometry(const scene::Cylinder& cylinder) {
        return point(cylinder.base) + ", " + point(cylinder.cap) + ", " + number(cylinder.radius);
    }
    // Negating z swaps which corner has the smaller z.
    static std::string geometry(const scene::Box& box) {
        return triple(box.min[0], box.min[1], -box.max[2]) + ", " + triple(box.max[0], box.max[1], -box.min[2]);
    }
    template <typename S>
    static const char* primitive(const scene::Transformed<S>& transformed) {
        return primitive(transformed.shape());
    }
    // The object-space primitive, then POV-Ray's matrix <…>: twelve numbers, the images of its x, y and z axes
    // and the translation, for row vectors (p' = p·M). Its world is ours with z negated, Z = diag(1, 1, −1), so
    // it takes Z·L·Z and Z·t.
    template <typename S>
    static std::string geometry(const scene::Transformed<S>& transformed) {
        return geometry(transformed.shape()) + " " + matrix(transformed.to_world());
    }
    static std::string matrix(const scene::Transform& m) {
        auto flip = [](int axis) { return axis == 2 ? -1.0 : 1.0; };
        std::string entries;
        for (int column = 0; column < 3; ++column) {
            for (int row = 0; row < 3; ++row) {
                entries += number(flip(row) * flip(column) * m.linear.row[row][column]) + ", ";
            }
        }
        entries += number(m.translation[0]) + ", " + number(m.translation[1]) + ", " + number(-m.translation[2]);
        return "matrix <" + entries + ">";
    }

    void appearance(int leaf, int material_index, int indent, Pass pass) {
        const auto material = static_cast<std::size_t>(material_index);
        const scene::Material& m = scene_.materials.at(material);
        if (pass == Pass::object_ids) {
            int id = leaf + 1;
            if (id > 65535) {
                throw std::invalid_argument("the object-id pass encodes at most 65535 primitives");
            }
            // ambient 1 under white ambient light: the pixel is the pigment, id/255 per channel, which
            // an 8-bit PNG stores exactly.
            line(indent, "pigment { color rgb " + triple((id % 256) / 255.0, (id / 256) / 255.0, 0) + " }");
            line(indent, "finish { ambient 1 diffuse 0 }");
            return;
        }
        if (pass == Pass::shadow_caster) {
            // A shadow ray keeps the pigment's transmit at each surface it crosses, as ours keeps t.
            line(indent, "pigment { color rgbt <0, 0, 0, " + number(m.transmission) + "> }");
            return;
        }
        const PovMaterial& p = materials_.at(material);
        line(indent, "// material " + scene_.material_names.at(material));
        line(indent, "texture {");
        // rgbt: transmitted light and light through shadows are weighed by the transmit, uncoloured.
        line(indent + 1, "pigment { color rgbt <" + number(m.color[0]) + ", " + number(m.color[1]) + ", " +
                             number(m.color[2]) + ", " + number(p.transmit) + "> }");
        std::string finish = "finish { ambient " + number(m.ambient * p.own_scale) + " diffuse " +
                             number(m.diffuse * p.own_scale) + " phong " + number(m.phong) + " phong_size " +
                             number(m.phong_size) + " reflection " + number(m.reflection);
        // Every primitive of an object with a shared interior carries its k (see InteriorPlan).
        double k = plan_.shared ? plan_.refraction : p.refraction;
        if (k != 1) {
            finish += " refraction " + number(k);
        }
        line(indent + 1, finish + " }");
        line(indent, "}");
        if (m.transmission > 0 && !plan_.shared) {
            line(indent, "interior { ior " + number(m.ior) + " }");
        }
    }

    const scene::Scene& scene_;
    bool object_ids_;
    std::vector<PovMaterial> materials_;  // by material index
    InteriorPlan plan_;                   // of the top-level object being written
    std::string text_;
};

}  // namespace

std::string export_pov(const scene::Scene& scene, int width, int height) {
    return Writer(scene, false).write(width, height);
}

std::string export_pov_object_ids(const scene::Scene& scene, int width, int height) {
    return Writer(scene, true).write(width, height);
}

}  // namespace twinray::pov
