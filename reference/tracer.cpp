#include "reference/tracer.h"

#include "reference/csg.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <type_traits>

namespace twinray::reference {
namespace {

template <typename T>
Shape<T> compile(const scene::Object& object) {
    return std::visit(
        [&](const auto& shape) -> Shape<T> {
            if constexpr (scene::is_primitive<std::decay_t<decltype(shape)>>) {
                return make_shape<T>(shape, object.leaf);
            } else {
                static_assert(std::is_same_v<std::decay_t<decltype(shape)>, scene::Csg>);
                CsgNode<T> node{shape.op, {}};
                for (const scene::Object& child : shape.children) {
                    node.children.push_back(compile<T>(child));
                }
                return node;
            }
        },
        object.shape);
}

// 1 for a primitive, a CSG object's leaves (at most scene::max_csg_leaves, so the recursion is shallow).
std::size_t primitives_in(const scene::Object& object) {
    const auto* csg = std::get_if<scene::Csg>(&object.shape);
    if (csg == nullptr) {
        return 1;
    }
    std::size_t count = 0;
    for (const scene::Object& child : csg->children) {
        count += primitives_in(child);
    }
    return count;
}

template <typename T>
SpanList<T> spans_of(const Shape<T>& shape, const Ray<T>& ray) {
    if (const auto* solid = std::get_if<PlacedSolid<T>>(&shape)) {
        const math::Transform<T>& m = solid->instance.to_world;
        T stretch;
        SpanList<T> spans = spans_of(solid->shape->tree, unit_object_ray(m, ray, stretch));
        for (Span<T>& span : spans) {
            for (Crossing<T>* crossing : {&span.enter, &span.exit}) {
                carry_back(m, stretch, *crossing);
                if (crossing->leaf >= 0) {
                    crossing->part = crossing->leaf;
                    crossing->leaf = solid->instance.leaf;
                }
            }
        }
        return spans;
    }
    if (const auto* node = std::get_if<CsgNode<T>>(&shape)) {
        SpanList<T> spans = spans_of(node->children.front(), ray);
        for (std::size_t i = 1; i < node->children.size(); ++i) {
            SpanList<T> other = spans_of(node->children[i], ray);
            switch (node->op) {
                case scene::CsgOp::union_: spans = csg_union(spans, other); break;
                case scene::CsgOp::intersection: spans = csg_intersection(spans, other); break;
                case scene::CsgOp::difference: spans = csg_difference(spans, other); break;
            }
        }
        return spans;
    }
    return std::visit(
        [&](const auto& primitive) -> SpanList<T> {
            using S = std::decay_t<decltype(primitive)>;
            if constexpr (std::is_same_v<S, CsgNode<T>> || std::is_same_v<S, PlacedSolid<T>>) {
                return {};
            } else {
                auto span = span_of(primitive, ray);
                return span ? SpanList<T>{*span} : SpanList<T>{};
            }
        },
        shape);
}

// An instance of a solid shape has none: its parts are its shape's.
template <typename T>
void collect_leaf_shapes(const Shape<T>& shape, std::vector<PrimitiveShape<T>>& leaves) {
    std::visit(
        [&](const auto& s) {
            using S = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<S, CsgNode<T>>) {
                for (const Shape<T>& child : s.children) {
                    collect_leaf_shapes<T>(child, leaves);
                }
            } else if constexpr (std::is_same_v<S, PlacedSolid<T>>) {
                return;
            } else {
                leaves[static_cast<std::size_t>(s.leaf)] = s;
            }
        },
        shape);
}

template <typename T>
Material<T> convert(const scene::Material& m) {
    auto s = [](double v) { return static_cast<T>(v); };
    return {Color<T>(m.color), s(m.ambient),    s(m.diffuse),      s(m.phong),
            s(m.phong_size),   s(m.reflection), s(m.transmission), s(m.ior)};
}

// Mirror direction of d about n.
template <typename T>
Vec3<T> reflect(Vec3<T> d, Vec3<T> n) {
    return d - T(2) * dot(d, n) * n;
}

// Snell's law with n facing the incoming ray and eta = n_from / n_to; nullopt on total internal
// reflection.
template <typename T>
std::optional<Vec3<T>> refract(Vec3<T> d, Vec3<T> n, T eta) {
    T cos_incident = -dot(d, n);
    T sin2_transmitted = eta * eta * (T(1) - cos_incident * cos_incident);
    if (sin2_transmitted > T(1)) {
        return std::nullopt;
    }
    T cos_transmitted = std::sqrt(T(1) - sin2_transmitted);
    return normalize(eta * d + (eta * cos_incident - cos_transmitted) * n);
}

// The ray tree (twinray probe) records a ray before it is shaded; without a tree, one null test.
template <typename T>
int record_ray(RayTree* tree, RayKind kind, int depth, int parent, const Ray<T>& ray,
               const std::optional<Hit<T>>& hit) {
    if (tree == nullptr) [[likely]] {
        return -1;
    }
    int index = tree->add(kind, depth, parent, recorded(ray.origin), recorded(ray.direction));
    if (hit) {
        tree->set_hit(index, hit->leaf, hit->triangle, hit->part, static_cast<double>(hit->t), recorded(hit->point),
                      recorded(hit->normal), hit->entering);
    }
    return index;
}

}  // namespace

template <typename T>
Tracer<T>::Tracer(const scene::Scene& scene, Accel accel, const ExternalIntersector<T>* external)
    : camera_(math::camera_basis(Vec3<T>(scene.camera.eye), Vec3<T>(scene.camera.look_at), Vec3<T>(scene.camera.up),
                                 scene.camera.fov_deg, [](Vec3<T> v) { return normalize(v); })),
      background_(scene.background),
      ambient_light_(scene.ambient_light),
      max_depth_(scene.max_depth),
      depth_control_(scene),
      leaf_materials_(scene.leaf_materials),
      external_(external) {
    for (const scene::Material& material : scene.materials) {
        materials_.push_back(convert<T>(material));
    }
    for (const scene::Light& light : scene.lights) {
        lights_.push_back({Vec3<T>(light.position), Color<T>(light.color)});
    }
    leaf_shapes_.resize(scene.leaf_paths.size());
    std::vector<scene::Bounds> bounds;
    std::size_t bounded_primitives = 0;
    for (const scene::Object& object : scene.objects) {
        objects_.push_back(compile<T>(object));
        collect_leaf_shapes<T>(objects_.back(), leaf_shapes_);
        bounds.push_back(scene::bounds(object));
        bounded_primitives += ObjectBvh<T>::is_finite(bounds.back()) ? primitives_in(object) : 0;
    }
    std::vector<std::shared_ptr<const SolidShape<T>>> solid_shapes;
    std::vector<scene::Bounds> solid_bounds;
    for (const scene::SolidShape& shape : scene.solid_shapes) {
        auto compiled =
            std::make_shared<SolidShape<T>>(SolidShape<T>{compile<T>(shape.tree), {}, shape.part_materials});
        compiled->parts.resize(shape.part_paths.size());
        collect_leaf_shapes<T>(compiled->tree, compiled->parts);
        solid_shapes.push_back(std::move(compiled));
        solid_bounds.push_back(scene::bounds(shape.tree));
    }
    first_solid_instance_ = objects_.size();
    for (const scene::SolidInstance& instance : scene.solid_instances) {
        const auto shape = static_cast<std::size_t>(instance.placement.shape);
        objects_.push_back(PlacedSolid<T>{solid_shapes[shape], make_instance<T>(instance.placement, instance.leaf),
                                          instance.material});
        bounds.push_back(scene::placed_bounds(solid_bounds[shape], instance.placement.transform()));
        bounded_primitives += ObjectBvh<T>::is_finite(bounds.back()) ? scene.solid_shapes[shape].part_paths.size() : 0;
    }
    if (accel == Accel::bvh || (accel == Accel::automatic && bounded_primitives > bvh_crossover)) {
        bvh_ = ObjectBvh<T>(bounds);
    }
    for (const scene::MeshShape& shape : scene.mesh_shapes) {
        mesh_shapes_.push_back(make_shape<T>(*shape.data, -1, accel));
    }
    std::vector<scene::Bounds> shape_bounds;
    for (const scene::MeshShape& shape : scene.mesh_shapes) {
        shape_bounds.push_back(scene::vertex_bounds(*shape.data));
    }
    std::vector<scene::Bounds> instance_bounds;
    for (const scene::Mesh& mesh : scene.meshes) {
        if (!mesh.placement) {
            meshes_.push_back(make_shape<T>(mesh, accel));
            continue;
        }
        instances_.push_back(make_instance<T>(*mesh.placement, mesh.leaf));
        instance_bounds.push_back(scene::placed_bounds(shape_bounds[static_cast<std::size_t>(mesh.placement->shape)],
                                                       mesh.placement->transform()));
    }
    // An instance's test carries the ray into its space and walks its shape's BVH: many box tests' worth.
    if (accel != Accel::none) {
        instance_bvh_ = ObjectBvh<T>(instance_bounds);
    }
}

template <typename T>
template <typename Limit, typename Visit>
void Tracer<T>::for_each_instance_crossing(const Ray<T>& ray, Limit&& limit, Visit&& visit) const {
    auto test = [&](std::size_t index) {
        const Instance<T>& instance = instances_[index];
        for_each_crossing(mesh_shapes_[instance.shape], object_ray(instance, ray), limit,
                          [&](const TriangleCrossing<T>& crossing) { visit(instance, crossing); });
    };
    if (instance_bvh_.empty()) {
        for (std::size_t i = 0; i < instances_.size(); ++i) {
            test(i);
        }
        return;
    }
    instance_bvh_.for_each_met(ray, limit, test);
}

template <typename T>
template <typename Limit, typename Visit>
void Tracer<T>::for_each_candidate(const Ray<T>& ray, Limit&& limit, Visit&& visit) const {
    if (bvh_.empty()) {
        for (std::size_t i = 0; i < objects_.size(); ++i) {
            visit(i);
        }
        return;
    }
    for (std::uint32_t i : bvh_.unbounded()) {
        visit(i);
    }
    bvh_.for_each_met(ray, limit, visit);
}

template <typename T>
int Tracer<T>::material_index(int leaf, int part) const {
    if (part < 0) {
        return leaf_materials_[static_cast<std::size_t>(leaf)];
    }
    const PlacedSolid<T>& solid = solid_instance(leaf);
    const int own = solid.shape->part_materials[static_cast<std::size_t>(part)];
    return own >= 0 ? own : solid.material;
}

template <typename T>
const PlacedSolid<T>& Tracer<T>::solid_instance(int leaf) const {
    auto leaf_of = [](const Shape<T>& object) { return std::get<PlacedSolid<T>>(object).instance.leaf; };
    auto found = std::lower_bound(objects_.begin() + static_cast<std::ptrdiff_t>(first_solid_instance_), objects_.end(),
                                  leaf, [&](const Shape<T>& object, int wanted) { return leaf_of(object) < wanted; });
    return std::get<PlacedSolid<T>>(*found);
}

template <typename T>
std::optional<Hit<T>> Tracer<T>::intersect(const Ray<T>& ray) const {
    if (!is_traceable(ray)) {
        return std::nullopt;
    }
    return first_hit(ray);
}

// A span list's first crossing after t = 0. Infinite ends (half-spaces) are not surfaces. The nearest hit's
// point is re-projected onto its primitive, which also gives the offset its secondary rays start at.
template <typename T>
std::optional<Hit<T>> Tracer<T>::first_hit(const Ray<T>& ray) const {
    if (external_ != nullptr) {
        return external_hit(ray);
    }
    std::optional<Hit<T>> nearest;
    auto limit = [&] { return nearest ? nearest->t : std::numeric_limits<T>::infinity(); };
    for_each_candidate(ray, limit, [&](std::size_t object) {
        for (const Span<T>& span : spans_of(objects_[object], ray)) {
            bool entering = span.enter.t > T(0);
            const Crossing<T>& crossing = entering ? span.enter : span.exit;
            if (!(crossing.t > T(0))) {
                continue;
            }
            // Nearer, or as near and earlier in the file (a smaller leaf, then within an instance a smaller part):
            // the object earlier in the file keeps the hit, in whatever order the objects come.
            if (crossing.leaf >= 0 &&
                (!nearest || crossing.t < nearest->t ||
                 (crossing.t == nearest->t && (crossing.leaf < nearest->leaf ||
                                               (crossing.leaf == nearest->leaf && crossing.part < nearest->part))))) {
                Vec3<T> facing = dot(crossing.outward_normal, ray.direction) > T(0) ? -crossing.outward_normal
                                                                                    : crossing.outward_normal;
                nearest = Hit<T>{crossing.t, ray.at(crossing.t), facing, crossing.leaf, -1, entering, T(0),
                                 facing,     crossing.part};
            }
            break;
        }
    });
    // Ties at equal t: the earlier leaf, then within a mesh the lower triangle.
    auto nearer = [&](T t, int leaf, int triangle) {
        return !nearest || t < nearest->t ||
               (t == nearest->t && (leaf < nearest->leaf || (leaf == nearest->leaf && triangle < nearest->triangle)));
    };
    const MeshShape<T>* hit_mesh = nullptr;
    for (const MeshShape<T>& mesh : meshes_) {
        for_each_crossing(mesh, ray, limit, [&](const TriangleCrossing<T>& crossing) {
            int triangle = static_cast<int>(crossing.triangle);
            if (nearer(crossing.t, mesh.leaf, triangle)) {
                Vec3<T> front = front_normal(mesh, crossing.triangle);
                Vec3<T> facing = crossing.front ? front : -front;
                nearest =
                    Hit<T>{crossing.t, ray.at(crossing.t), facing, mesh.leaf, triangle, crossing.front, T(0), facing};
                hit_mesh = &mesh;
            }
        });
    }
    const Instance<T>* hit_instance = nullptr;
    for_each_instance_crossing(ray, limit, [&](const Instance<T>& instance, const TriangleCrossing<T>& crossing) {
        int triangle = static_cast<int>(crossing.triangle);
        if (nearer(crossing.t, instance.leaf, triangle)) {
            Vec3<T> facing = facing_normal(instance, mesh_shapes_[instance.shape], crossing);
            nearest = Hit<T>{crossing.t, ray.at(crossing.t),
                             facing,     instance.leaf,
                             triangle,   crossing.front != instance.mirrors,
                             T(0),       facing};
            hit_instance = &instance;
        }
    });
    if (nearest) {
        project_onto_surface(*nearest, hit_mesh, hit_instance);
    }
    return nearest;
}

template <typename T>
void Tracer<T>::project_onto_surface(Hit<T>& hit, const MeshShape<T>* mesh, const Instance<T>* instance) const {
    const auto triangle = static_cast<std::uint32_t>(hit.triangle);
    SurfacePoint<T> on_surface;
    if (instance != nullptr) {
        const MeshShape<T>& shape = mesh_shapes_[instance->shape];
        on_surface = surface_point(*instance, shape, triangle, hit.point);
        hit.point = on_surface.point;
        hit.shading_normal = shading_normal(*instance, shape, triangle, hit.point, hit.normal);
    } else if (mesh != nullptr) {
        on_surface = surface_point(*mesh, triangle, hit.point, hit.normal);
        hit.point = on_surface.point;
        hit.shading_normal = shading_normal(*mesh, triangle, hit.point, hit.normal);
    } else if (hit.part >= 0) {
        const PlacedSolid<T>& solid = solid_instance(hit.leaf);
        const math::Transform<T>& m = solid.instance.to_world;
        on_surface = placed_surface_point(m, solid.instance.norms, hit.point, [&](Vec3<T> object_point) {
            return std::visit(
                [&](const auto& shape) {
                    return surface_point(shape, object_point, normalize(m.normal_to_object(hit.normal)));
                },
                solid.shape->parts[static_cast<std::size_t>(hit.part)]);
        });
        hit.point = on_surface.point;
    } else {
        on_surface = std::visit([&](const auto& shape) { return surface_point(shape, hit.point, hit.normal); },
                                leaf_shapes_[static_cast<std::size_t>(hit.leaf)]);
        hit.point = on_surface.point;
    }
    hit.spawn_offset = on_surface.spawn_offset;
}

// The hit keeps the intersector's point, so that its error is the intersector's; its secondary rays start off it by
// its distance from the surface plus the reference's bound there, widened by the ratio of unit roundoffs (the
// bound is linear in u), so that the intersector's own decision on which side a ray starts stays on the right one.
template <typename T>
std::optional<Hit<T>> Tracer<T>::external_hit(const Ray<T>& ray) const {
    std::optional<ExternalCrossing<T>> crossing = external_->nearest(ray);
    if (!crossing) {
        return std::nullopt;
    }
    // Normalised again: the re-projection onto a curved surface needs it unit to T's precision, which the
    // intersector's need not be (a sphere's (p - c) / r is as far from unit as p is from the surface).
    const Vec3<T> outward = normalize(crossing->outward_normal);
    Vec3<T> facing = dot(outward, ray.direction) > T(0) ? -outward : outward;
    Hit<T> hit{crossing->t,        ray.at(crossing->t), facing, crossing->leaf,
               crossing->triangle, crossing->entering,  T(0),   facing};
    auto by_leaf = [](const auto& item, int leaf) { return item.leaf < leaf; };
    auto mesh = std::lower_bound(meshes_.begin(), meshes_.end(), hit.leaf, by_leaf);
    auto instance = std::lower_bound(instances_.begin(), instances_.end(), hit.leaf, by_leaf);
    const Vec3<T> found = hit.point;
    project_onto_surface(hit, mesh != meshes_.end() && mesh->leaf == hit.leaf ? &*mesh : nullptr,
                         instance != instances_.end() && instance->leaf == hit.leaf ? &*instance : nullptr);
    const T widening = std::max(T(1), external_->unit_roundoff() / (std::numeric_limits<T>::epsilon() / 2));
    hit.spawn_offset = length(found - hit.point) + widening * hit.spawn_offset;
    hit.point = found;
    return hit;
}

template <typename T>
T Tracer<T>::shadow_transmittance(Vec3<T> origin, Vec3<T> light_position) const {
    Vec3<T> to_light = light_position - origin;
    T distance = length(to_light);
    Ray<T> ray{origin, to_light / distance};
    T transmittance = T(1);
    if (external_ != nullptr) {
        // Every surface crossed before the light, multiplied in leaf order (file order, as below).
        std::vector<int> crossed;
        for (const ExternalCrossing<T>& crossing : external_->crossings(ray, distance)) {
            crossed.push_back(crossing.leaf);
        }
        std::sort(crossed.begin(), crossed.end());
        for (int leaf : crossed) {
            transmittance *= material_of(leaf).transmission;
        }
        return transmittance;
    }
    // Multiplies in the transmission of each surface of the object crossed before the light; false once
    // nothing gets through.
    auto passes = [&](const Shape<T>& object) {
        for (const Span<T>& span : spans_of(object, ray)) {
            for (const Crossing<T>* crossing : {&span.enter, &span.exit}) {
                if (crossing->leaf >= 0 && crossing->t > T(0) && crossing->t < distance) {
                    transmittance *= material_of(crossing->leaf, crossing->part).transmission;
                }
            }
            if (transmittance == T(0)) {
                return false;
            }
        }
        return true;
    };
    if (bvh_.empty()) {
        for (const Shape<T>& object : objects_) {
            if (!passes(object)) {
                return transmittance;
            }
        }
        return meshes_transmittance(ray, distance, transmittance);
    }
    // Float products depend on their order: the objects the BVH finds are multiplied in the file's order.
    std::vector<std::size_t> met;
    for_each_candidate(
        ray, [&] { return distance; }, [&](std::size_t object) { met.push_back(object); });
    std::sort(met.begin(), met.end());
    for (std::size_t object : met) {
        if (!passes(objects_[object])) {
            return transmittance;
        }
    }
    return meshes_transmittance(ray, distance, transmittance);
}

// Each triangle crossed strictly before the light multiplies in its mesh's transmission, mesh after mesh in
// file order, after the objects, then instance after instance in file order; all of a mesh's factors are equal,
// so the order its BVH finds them in cannot change the product. Once nothing gets through, the walk's limit
// drops below 0 and it stops.
template <typename T>
T Tracer<T>::meshes_transmittance(const Ray<T>& ray, T distance, T transmittance) const {
    auto limit = [&] { return transmittance == T(0) ? T(-1) : distance; };
    for (const MeshShape<T>& mesh : meshes_) {
        T surface = material_of(mesh.leaf).transmission;
        for_each_crossing(mesh, ray, limit, [&](const TriangleCrossing<T>& crossing) {
            if (crossing.t < distance) {
                transmittance *= surface;
            }
        });
        if (transmittance == T(0)) {
            return transmittance;
        }
    }
    if (instances_.empty()) {
        return transmittance;
    }
    // The leaf of every instance triangle crossed before the light, multiplied in file order.
    std::vector<int> crossed;
    for_each_instance_crossing(
        ray, [&] { return distance; },
        [&](const Instance<T>& instance, const TriangleCrossing<T>& crossing) {
            if (crossing.t < distance) {
                crossed.push_back(instance.leaf);
            }
        });
    std::sort(crossed.begin(), crossed.end());
    for (int leaf : crossed) {
        transmittance *= material_of(leaf).transmission;
    }
    return transmittance;
}

template <typename T>
int Tracer<T>::mesh_crossings(const Ray<T>& ray, T distance) const {
    int count = 0;
    if (!is_traceable(ray)) {
        return count;
    }
    if (external_ != nullptr) {
        for (const ExternalCrossing<T>& crossing : external_->crossings(ray, distance)) {
            count += crossing.triangle >= 0 ? 1 : 0;
        }
        return count;
    }
    for (const MeshShape<T>& mesh : meshes_) {
        for_each_crossing(
            mesh, ray, [&] { return distance; },
            [&](const TriangleCrossing<T>& crossing) { count += crossing.t < distance ? 1 : 0; });
    }
    for_each_instance_crossing(
        ray, [&] { return distance; },
        [&](const Instance<T>&, const TriangleCrossing<T>& crossing) { count += crossing.t < distance ? 1 : 0; });
    return count;
}

// Secondary rays start off the surface, on the side they leave to, by the hit's spawn_offset: the bound on
// the re-projected point's rounding error plus that of the next ray's decision on which side of the
// surface it starts (SurfacePoint, ray.h). With the origin off the surface, the new ray accepts any hit
// with t > 0.
template <typename T>
Vec3<T> Tracer<T>::spawn_origin(const Hit<T>& hit, Vec3<T> direction) {
    T side = dot(direction, hit.normal) >= T(0) ? T(1) : T(-1);
    return hit.point + (side * hit.spawn_offset) * hit.normal;
}

template <typename T>
Color<T> Tracer<T>::trace(const Ray<T>& ray, int depth, TraceTally* tally, RayTree* tree) const {
    if (!is_traceable(ray)) {
        return background_;
    }
    TreeWalk walk{0, {}, tree};
    Color<T> color = trace_ray(ray, depth, scene::DepthControl::primary(), walk, RayKind::primary, -1);
    if (tally != nullptr) {
        tally->add_pixel(walk.rays, walk.ledger.dropped, walk.ledger.over_budget);
    }
    return color;
}

template <typename T>
Color<T> Tracer<T>::trace_ray(const Ray<T>& ray, int depth, const scene::RayShare& share, TreeWalk& walk, RayKind kind,
                              int parent) const {
    ++walk.rays;
    ++walk.ledger.traced;
    std::optional<Hit<T>> hit = first_hit(ray);
    int node = record_ray(walk.tree, kind, depth, parent, ray, hit);
    Color<T> color = hit ? shade(ray, *hit, depth, share, walk, node) : background_;
    if (walk.tree != nullptr) [[unlikely]] {
        walk.tree->set_total_color(node, recorded(color));
    }
    return color;
}

template <typename T>
bool Tracer<T>::admits(const scene::RayShare& share, int depth, TreeWalk& walk, RayKind kind, int parent) const {
    scene::DropReason reason = depth_control_.decide(share, depth, walk.ledger);
    if (reason == scene::DropReason::traced) {
        return true;
    }
    if (walk.tree != nullptr) [[unlikely]] {
        walk.tree->add_dropped(parent, kind, depth, share.weight, share.weight * depth_control_.radiance_bound(depth),
                               reason == scene::DropReason::budget);
    }
    return false;
}

// I = ambient·C·ambient_light + Σ_lights shadow·(diffuse·C·Lc·(N·L) + phong·Lc·max(0, R·L)^phong_size)
//   + reflection·I(reflected) + transmission·I(refracted)          (docs/scene-format.md, "Shading")
template <typename T>
Color<T> Tracer<T>::shade(const Ray<T>& ray, const Hit<T>& hit, int depth, const scene::RayShare& share, TreeWalk& walk,
                          int node) const {
    RayTree* tree = walk.tree;
    const Material<T>& m = material_of(hit.leaf, hit.part);
    Color<T> color = m.ambient * (m.color * ambient_light_);
    const Vec3<T>& shading = hit.shading_normal;
    Vec3<T> mirror = reflect(ray.direction, shading);
    for (const Light<T>& light : lights_) {
        Vec3<T> to_light = normalize(light.position - hit.point);
        T lambert = dot(shading, to_light);
        if (!(lambert > T(0))) {
            if (tree != nullptr) [[unlikely]] {
                tree->add_light_facing_away(node, static_cast<double>(lambert));
            }
            continue;
        }
        ++walk.rays;
        Vec3<T> shadow_origin = spawn_origin(hit, to_light);
        T shadow = shadow_transmittance(shadow_origin, light.position);
        if (tree != nullptr) [[unlikely]] {
            tree->add_light(node, static_cast<double>(lambert), static_cast<double>(shadow), recorded(shadow_origin),
                            recorded(normalize(light.position - shadow_origin)));
        }
        if (shadow == T(0)) {
            continue;
        }
        Color<T> diffuse = (m.diffuse * lambert) * (m.color * light.color);
        T highlight = m.phong > T(0) ? m.phong * std::pow(std::fmax(T(0), dot(mirror, to_light)), m.phong_size) : T(0);
        color += shadow * (diffuse + highlight * light.color);
    }
    if (tree != nullptr) [[unlikely]] {
        tree->set_local_color(node, recorded(color));
    }
    if (depth >= max_depth_) {
        return color;
    }
    // Each child is traced only if the depth control admits it (scene/depth_control.h).
    int material = material_index(hit.leaf, hit.part);
    std::uint32_t traced_before_children = walk.ledger.traced;
    T reflection = m.reflection;
    bool total_internal = false;
    if (m.transmission > T(0)) {
        T eta = hit.entering ? T(1) / m.ior : m.ior;
        if (std::optional<Vec3<T>> refracted = refract(ray.direction, shading, eta)) {
            scene::RayShare child = depth_control_.refracted(share, material);
            if (admits(child, depth + 1, walk, RayKind::refracted, node)) {
                Ray<T> next{spawn_origin(hit, *refracted), *refracted};
                color += m.transmission * trace_ray(next, depth + 1, child, walk, RayKind::refracted, node);
            }
        } else {
            reflection += m.transmission;
            total_internal = true;
        }
    }
    if (reflection > T(0)) {
        scene::RayShare child =
            depth_control_.reflected(share, material, total_internal, walk.ledger.traced - traced_before_children);
        if (admits(child, depth + 1, walk, RayKind::reflected, node)) {
            Ray<T> next{spawn_origin(hit, mirror), mirror};
            color += reflection * trace_ray(next, depth + 1, child, walk, RayKind::reflected, node);
        }
    }
    return color;
}

template <typename T>
Ray<T> Tracer<T>::primary_ray(int x, int y, int width, int height) const {
    T half_height = camera_.half_width * static_cast<T>(height) / static_cast<T>(width);
    T u = (T(2) * (static_cast<T>(x) + T(0.5)) / static_cast<T>(width) - T(1)) * camera_.half_width;
    T v = (T(1) - T(2) * (static_cast<T>(y) + T(0.5)) / static_cast<T>(height)) * half_height;
    return {camera_.eye, normalize(camera_.forward + u * camera_.right + v * camera_.up)};
}

template <typename T>
RenderResult render(const scene::Scene& scene, const RenderOptions& options, const ExternalIntersector<T>* external) {
    return render(Tracer<T>(scene, options.accel, external), scene, options);
}

template <typename T>
RenderResult render(const Tracer<T>& tracer, const scene::Scene& scene, const RenderOptions& options) {
    scene::ImageSize size = scene::resolve_image_size(scene, options.width, options.height);
    Image image(size.width, size.height);
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = process_cpu_seconds();
    TraceTally tally = parallel_sum<TraceTally>(
        size.height, options.threads,
        [&](int y) {
            TraceTally row;
            for (int x = 0; x < size.width; ++x) {
                TraceTally pixel;
                Color<T> c = tracer.trace(tracer.primary_ray(x, y, size.width, size.height), 1, &pixel);
                image.at(x, y) = {static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)};
                row.add(pixel, y * size.width + x);
            }
            return row;
        },
        options.progress, options.cancel);
    return {std::move(image), tally, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
            process_cpu_seconds() - cpu_start};
}

template class Tracer<double>;
template class Tracer<float>;
template RenderResult render<double>(const scene::Scene&, const RenderOptions&, const ExternalIntersector<double>*);
template RenderResult render<float>(const scene::Scene&, const RenderOptions&, const ExternalIntersector<float>*);
template RenderResult render<double>(const Tracer<double>&, const scene::Scene&, const RenderOptions&);
template RenderResult render<float>(const Tracer<float>&, const scene::Scene&, const RenderOptions&);

}  // namespace twinray::reference
