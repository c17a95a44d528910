#include "sse/compiled_scene.h"

#include "math/rounding.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

namespace twinray::sse {

InstanceRecord InstanceRecord::of(const scene::Transform& to_world, std::size_t shape, std::int32_t leaf,
                                  std::int32_t material) {
    InstanceRecord record;
    record.to_world = math::Transform<float>::from(to_world);
    record.norms = scene::transform_norms<float>(to_world);
    record.shape = static_cast<std::uint32_t>(shape);
    record.mirrors = math::determinant(to_world.linear) < 0 ? 1 : 0;
    record.leaf = leaf;
    record.material = material;
    return record;
}

namespace {

// Widened by a relative margin far beyond float rounding, so that culling never loses a hit.
scene::Box as_float_safe_box(const scene::Bounds& bounds) {
    scene::Box box;
    for (int axis = 0; axis < 3; ++axis) {
        double margin = 1e-4 * (std::fabs(bounds.low[axis]) + std::fabs(bounds.high[axis])) + 1e-30;
        box.min[axis] = bounds.low[axis] - margin;
        box.max[axis] = bounds.high[axis] + margin;
    }
    return box;
}

// A primitive's hit surface is made again from its packet record (surface_of) where it gives it back bit for bit, so
// that the leaf table can be made once the scene's objects are given up; the others are kept apart from the start.
template <typename Shape>
concept SurfaceFromRecord = requires(const Shape& record) {
    surface_of(record);
};

template <typename Shape, typename Surface>
bool gives_back(const Shape& record, const Surface& surface) {
    if constexpr (SurfaceFromRecord<Shape>) {
        const Surface again = surface_of(record);
        return std::memcmp(&again, &surface, sizeof surface) == 0;
    } else {
        return false;
    }
}

// A leaf whose record does not give back its surface: a transformed primitive's, or a sphere's or cylinder's whose
// radius squared in float is not normal.
struct LeafApart {
    std::int32_t leaf;
    Leaf entry;
};

// Appends a primitive to the list of its type (at top level, or inside one CSG object); returns where it went.
// `apart`, if given, receives its leaf's entry where its record does not give its surface back.
BvhItem add_primitive(PrimitiveLists& lists, const scene::Object& object, std::int32_t id, float transmission,
                      std::vector<LeafApart>* apart) {
    BvhItem added{};
    std::visit(
        [&](const auto& shape) {
            using S = std::decay_t<decltype(shape)>;
            if constexpr (scene::is_primitive<S>) {
                PrimitiveListOf<S>& list = lists.of<S>();
                added = {list_index_of<S>(), static_cast<std::uint32_t>(list.items.size())};
                list.items.push_back(make_shape(shape));
                list.ids.push_back(id);
                list.transmission.push_back(transmission);
                const SurfaceOf<S> surface = make_surface(shape);
                if (apart != nullptr && !gives_back(list.items.back(), surface)) {
                    apart->push_back({object.leaf, {surface, object.material}});
                }
            }
        },
        object.shape);
    return added;
}

// The leaf table's entries for the records of `lists` that give back their surfaces; `leaf_of` maps an id to its leaf.
template <typename LeafOf>
void add_leaves_from_records(LeafTable& leaves, const PrimitiveLists& lists, const std::vector<int>& leaf_materials,
                             LeafOf leaf_of) {
    lists.for_each([&](const auto& list) {
        using Shape = typename std::decay_t<decltype(list)>::shape_type;
        if constexpr (SurfaceFromRecord<Shape>) {
            for (std::size_t i = 0; i < list.items.size(); ++i) {
                const auto leaf = static_cast<std::size_t>(leaf_of(list.ids[i]));
                leaves[leaf] = {surface_of(list.items[i]), leaf_materials[leaf]};
            }
        }
    });
}

// What brute force spends on the object per packet, in sphere tests (relative_test_cost): a CSG object its
// leaves' and 2.2 more, for its bound and the fold of its spans (measured as the primitives' costs are).
double brute_force_cost(const scene::Object& object) {
    return std::visit(
        [](const auto& shape) {
            using S = std::decay_t<decltype(shape)>;
            if constexpr (scene::is_primitive<S>) {
                return relative_test_cost<ShapeOf<S>>;
            } else {
                double cost = 0;
                for (const scene::Object& child : shape.children) {
                    cost += brute_force_cost(child);
                }
                return cost;
            }
        },
        object.shape);
}
constexpr double csg_object_cost = 2.2;

bool is_finite(const scene::Bounds& bounds) {
    for (int axis = 0; axis < 3; ++axis) {
        if (!std::isfinite(bounds.low[axis]) || !std::isfinite(bounds.high[axis])) {
            return false;
        }
    }
    return true;
}

// Compiles the scene moved by −origin_of(scene) in double (each coordinate and plane offset rounded once in
// double, then once to float), so the float records hold small numbers.
class Compiler {
public:
    Compiler(const scene::Scene& scene, Accel accel, scene::Scene* given_up)
        : origin_(origin_of(scene)),
          moved_(origin_ == scene::Vec3{0, 0, 0} ? std::nullopt
                                                 : std::optional<scene::Scene>(scene::moved(scene, 1, -origin_))),
          scene_(moved_ ? *moved_ : scene),
          accel_(accel),
          given_up_(given_up) {}

    CompiledScene run() {
        CompiledScene out(scene_);
        out.origin = origin_;
        give_up(&scene::Scene::leaf_paths);  // never read here
        for (const scene::Material& m : scene_.materials) {
            out.materials.push_back({Color(m.color), static_cast<float>(m.ambient), static_cast<float>(m.diffuse),
                                     static_cast<float>(m.phong), static_cast<float>(m.phong_size),
                                     static_cast<float>(m.reflection), static_cast<float>(m.transmission),
                                     static_cast<float>(m.ior)});
        }
        // The leaves of instances, which the leaf table leaves out: their records name their hits.
        std::vector<std::int32_t> instance_leaves;
        std::size_t mesh_instances = 0;
        for (const scene::Mesh& mesh : scene_.meshes) {
            if (mesh.placement) {
                instance_leaves.push_back(mesh.leaf);
                ++mesh_instances;
            }
        }
        for (const scene::SolidInstance& instance : scene_.solid_instances) {
            instance_leaves.push_back(instance.leaf);
        }
        std::sort(instance_leaves.begin(), instance_leaves.end());
        // Reserved, not grown: a million primitives would otherwise be copied some twenty times over.
        scene::PrimitiveTypes::for_each([&](auto type) {
            using S = typename decltype(type)::type;
            out.primitives.of<S>().reserve(static_cast<std::size_t>(
                std::count_if(scene_.objects.begin(), scene_.objects.end(),
                              [](const scene::Object& object) { return std::holds_alternative<S>(object.shape); })));
        });
        std::vector<scene::Bounds> solid_bounds;
        for (const scene::SolidShape& shape : scene_.solid_shapes) {
            out.solids.push_back(compile_solid(shape));
            solid_bounds.push_back(scene::bounds(shape.tree));
        }
        out.solid_instances.reserve(scene_.solid_instances.size());
        std::vector<double> shape_costs;
        std::vector<scene::Bounds> shape_bounds;
        for (const scene::MeshShape& shape : scene_.mesh_shapes) {
            shape_bounds.push_back(scene::vertex_bounds(*shape.data));
            out.shapes.push_back(compile_shape(*shape.data, shape_bounds.back()));
            shape_costs.push_back(shape_cost(out.shapes.back()));
        }
        if (accel_ == Accel::automatic) {  // both walk every object: not paid where the choice is given
            out.brute_force_weight = bounded_cost(shape_costs);
            out.crossover = crossover();
        }
        const bool with_bvh = accel_ == Accel::bvh || (accel_ == Accel::automatic &&
                                                       out.brute_force_weight > static_cast<double>(out.crossover));
        // The BVH's inputs, made only for a BVH (32 bytes an item).
        LargeArray<BvhInput> bounded;
        if (with_bvh) {
            std::size_t mesh_items = 0;  // instances and triangles
            for (const scene::Mesh& mesh : scene_.meshes) {
                mesh_items += mesh.placement ? 1 : mesh.data->triangles.size();
            }
            bounded.reserve(scene_.objects.size() + scene_.solid_instances.size() + mesh_items);
        }
        std::vector<BvhItem> unbounded;
        bool bounded_besides_instances = false;  // a bounded item other than an instance of a mesh shape
        for (const scene::Object& object : scene_.objects) {
            BvhItem item;
            scene::Bounds bounds;
            if (const auto* csg = std::get_if<scene::Csg>(&object.shape)) {
                auto tree = std::make_shared<CsgTree>();
                add_csg_node(*tree, *csg, &apart_);
                bounds = add_csg_object(out, std::move(tree), scene::bounds(object), -1, item);
            } else {
                item = add_primitive(out.primitives, object, object.leaf, transmission_of(object), &apart_);
                bounds = scene::bounds(object);
            }
            if (!is_finite(bounds)) {
                unbounded.push_back(item);
                continue;
            }
            bounded_besides_instances = true;
            if (with_bvh) {
                bounded.emplace_back(bounds, item);
            }
        }
        for (std::size_t i = 0; i < scene_.solid_instances.size(); ++i) {
            const scene::SolidInstance& instance = scene_.solid_instances[i];
            const auto shape = static_cast<std::size_t>(instance.placement.shape);
            const scene::Transform to_world = instance.placement.transform();
            out.solid_instances.push_back(InstanceRecord::of(to_world, shape, instance.leaf, instance.material));
            BvhItem item;
            const scene::Bounds bounds =
                add_csg_object(out, out.solids[shape].tree, scene::placed_bounds(solid_bounds[shape], to_world),
                               static_cast<std::int32_t>(i), item);
            if (!is_finite(bounds)) {
                unbounded.push_back(item);
                continue;
            }
            bounded_besides_instances = true;
            if (with_bvh) {
                bounded.emplace_back(bounds, item);
            }
        }
        const bool any_smooth = std::any_of(scene_.meshes.begin(), scene_.meshes.end(), [](const scene::Mesh& mesh) {
            return !mesh.placement && mesh.data->smooth;
        });
        std::uint32_t instance_index = 0;
        for (const scene::Mesh& mesh : scene_.meshes) {
            if (!mesh.placement) {
                add_mesh(out, mesh, any_smooth, with_bvh ? &bounded : nullptr);
                bounded_besides_instances = true;
            } else if (with_bvh) {
                const auto shape = static_cast<std::size_t>(mesh.placement->shape);
                const scene::Transform to_world = mesh.placement->transform();
                bounded.emplace_back(scene::placed_bounds(shape_bounds[shape], to_world),
                                     BvhItem{instance_list, instance_index++},
                                     instance_item_padding(condition_of(scene::transform_norms<float>(to_world))));
            }
        }
        // The last reading of the scene's objects: they (72 bytes each) are given up before the build, and neither
        // they nor the build's arrays are held beside the leaf table (48 bytes a leaf), made from the records after.
        const bool in_bvh = with_bvh && !bounded.empty();
        add_culling_bounds(in_bvh ? out.unbounded : out.primitives, in_bvh);
        out.any_transparency = scene_.has_transparency();  // reads the objects' materials
        give_up(&scene::Scene::objects);
        if (with_bvh) {
            add_bvh(out, std::move(bounded), unbounded, out.any_transparency);
        }
        add_leaf_table(out, instance_leaves);
        // After the build, which keeps their order: its arrays and a million records (116 MB) are never held at once.
        add_instances(out, mesh_instances);
        if (!bounded_besides_instances && !out.instances.empty()) {
            double largest_condition = 0;
            for (const InstanceRecord& instance : out.instances) {
                largest_condition = std::max(largest_condition, condition_of(instance.norms));
            }
            out.top_ray_padding = static_cast<float>(instance_ray_padding(largest_condition));
        }
        // No mesh is read again: the scene's (136 bytes an instance) go before the boxes come.
        give_up(&scene::Scene::meshes);
        add_instance_boxes(out);
        for (const scene::Light& light : scene_.lights) {
            out.lights.push_back({Vec3(light.position), Color(light.color)});
        }
        out.background = Color(scene_.background);
        out.ambient_light = Color(scene_.ambient_light);
        out.max_depth = scene_.max_depth;
        out.any_inverse_direction = out.primitives.any_uses_inverse_direction() || !out.csg_objects.empty();
        const scene::Camera& camera = scene_.camera;
        out.camera = math::camera_basis(Vec3(camera.eye), Vec3(camera.look_at), Vec3(camera.up), camera.fov_deg,
                                        [](Vec3 v) { return math::normalize_by_reciprocal(v); });
        return out;
    }

private:
    // The primitives' entries from their records, the leaves kept apart, and the meshes'.
    void add_leaf_table(CompiledScene& out, const std::vector<std::int32_t>& instance_leaves) const {
        out.leaves.assign(scene_.leaf_materials.size(), instance_leaves);
        add_leaves_from_records(out.leaves, out.primitives, scene_.leaf_materials,
                                [](std::int32_t leaf) { return leaf; });
        for (const CsgObject& csg : out.csg_objects) {
            if (csg.instance < 0) {
                const CsgTree& tree = *csg.tree;
                add_leaves_from_records(out.leaves, tree.leaves, scene_.leaf_materials, [&](std::int32_t slot) {
                    return tree.slot_leaf[static_cast<std::size_t>(slot)];
                });
            }
        }
        for (const LeafApart& kept : apart_) {
            out.leaves[static_cast<std::size_t>(kept.leaf)] = kept.entry;
        }
        std::uint32_t mesh_index = 0;  // as add_mesh compiled them
        for (const scene::Mesh& mesh : scene_.meshes) {
            if (!mesh.placement) {
                out.leaves[static_cast<std::size_t>(mesh.leaf)] = {MeshSurface{mesh_index++}, mesh.material};
            }
        }
    }

    // Empties the list in the re-based copy, if there is one, and in the caller's scene if it gave it up.
    template <typename List>
    void give_up(List scene::Scene::*list) {
        for (scene::Scene* scene : {moved_ ? &*moved_ : nullptr, given_up_}) {
            if (scene != nullptr) {
                scene->*list = List();
            }
        }
    }

    // The BVH over `bounded`; the rest in the flat lists every ray tests, in their compiled order.
    static void add_bvh(CompiledScene& out, LargeArray<BvhInput> bounded, const std::vector<BvhItem>& unbounded,
                        bool keep_triangle_file_order) {
        const double cpu_start = process_cpu_seconds();
        out.bvh = build_bvh(std::move(bounded), primitive_bvh_costs);
        out.bvh_build_cpu_seconds = process_cpu_seconds() - cpu_start;
        std::uint32_t list_index = 0;
        out.primitives.for_each_pair(out.unbounded, [&](const auto& all, auto& kept) {
            for (const BvhItem& item : unbounded) {
                if (item.list == list_index) {
                    kept.push_back_from(all, item.index);
                }
            }
            ++list_index;
        });
        for (const BvhItem& item : unbounded) {
            if (item.list == csg_list) {
                out.unbounded_csg.push_back(static_cast<std::int32_t>(item.index));
            }
        }
        put_in_leaf_order(out, unbounded, keep_triangle_file_order);
    }

    // What the bounded items' weight is held against: lower where rays may be reflected or refracted.
    std::size_t crossover() const {
        const bool secondary_rays = scene_.max_depth > 1 && (scene_.has_reflection() || scene_.has_transparency());
        return secondary_rays ? bvh_crossover_with_secondary_rays : bvh_crossover;
    }

    // What the choice of a BVH weighs: what brute force would spend on the bounded items, in sphere tests.
    double bounded_cost(const std::vector<double>& shape_costs) const {
        double cost = 0;
        for (const scene::Object& object : scene_.objects) {
            if (is_finite(scene::bounds(object))) {
                cost +=
                    brute_force_cost(object) + (std::holds_alternative<scene::Csg>(object.shape) ? csg_object_cost : 0);
            }
        }
        for (const scene::SolidInstance& instance : scene_.solid_instances) {
            const scene::SolidShape& shape = scene_.solid_shapes[static_cast<std::size_t>(instance.placement.shape)];
            cost += transformed_trip_cost + brute_force_cost(shape.tree) + csg_object_cost;
        }
        std::size_t triangles = 0;
        for (const scene::Mesh& mesh : scene_.meshes) {
            if (mesh.placement) {
                cost += transformed_trip_cost + shape_costs[static_cast<std::size_t>(mesh.placement->shape)];
            } else {
                triangles += mesh.data->triangles.size() - mesh.data->degenerate.size();
            }
        }
        return cost + triangle_test_cost * static_cast<double>(triangles);
    }

    // The bounding spheres tile culling reads, for the lists every ray tests (CompiledScene::flat: every
    // primitive's, in file order, or with a BVH only the unbounded ones', so that a BVH's primitives hold none).
    void add_culling_bounds(PrimitiveLists& flat, bool only_unbounded) const {
        for (const scene::Object& object : scene_.objects) {
            std::visit(
                [&](const auto& shape) {
                    using S = std::decay_t<decltype(shape)>;
                    if constexpr (scene::is_primitive<S>) {
                        if (only_unbounded && is_finite(scene::bounds(object))) {
                            return;
                        }
                        PrimitiveListOf<S>& list = flat.of<S>();
                        const scene::BoundingSphere bound = scene::bounding_sphere(shape);
                        list.bound_centers.push_back(bound.center);
                        list.bound_radii.push_back(bound.radius);
                    }
                },
                object.shape);
        }
    }

    // Moves the primitives and the triangles into the order of the BVH's leaves (the unbounded primitives
    // after, in file order) and points the leaves' items at their new places: the walk then reads each leaf's
    // records one after the other instead of missing the cache on each (at a million primitives the lists far
    // exceed it). Where each primitive went is kept in bvh.file_order, and each triangle's, where shadow rays
    // multiply transmissions, in triangles.file_order.
    static void put_in_leaf_order(CompiledScene& out, const std::vector<BvhItem>& unbounded,
                                  bool keep_triangle_file_order) {
        constexpr std::size_t list_count = scene::PrimitiveTypes::size;
        std::size_t first[list_count];  // where each list's places begin in file_order
        std::uint32_t placed[list_count] = {};
        std::size_t count = 0, list_index = 0;
        out.primitives.for_each([&](const auto& list) {
            first[list_index++] = count;
            count += list.items.size();
        });
        out.bvh.file_order.resize(count);
        auto place = [&](const BvhItem& item) {
            std::uint32_t leaf_place = placed[item.list]++;
            out.bvh.file_order[first[item.list] + item.index] = leaf_place;
            return leaf_place;
        };
        LargeArray<std::uint32_t> destination(
            out.triangles.items.size());  // where the record now at each place belongs
        std::uint32_t triangles_placed = 0;
        // CSG objects keep their places.
        for (BvhItem& item : out.bvh.items) {
            if (item.list < csg_list) {
                item.index = place(item);
            } else if (item.list == triangle_list) {
                destination[item.index] = triangles_placed;
                item.index = triangles_placed++;
            }
        }
        for (const BvhItem& item : unbounded) {
            if (item.list < csg_list) {
                place(item);
            }
        }
        if (keep_triangle_file_order) {
            out.triangles.file_order = destination;
        }
        TriangleList& triangles = out.triangles;
        move_to_destinations(destination, [&](std::uint32_t i, std::uint32_t j) {
            std::swap(triangles.items[i], triangles.items[j]);
            if (!triangles.corners.empty()) {
                std::swap(triangles.corners[i], triangles.corners[j]);
            }
        });
        list_index = 0;
        auto permute = [&](auto& records) {
            const auto begin = out.bvh.file_order.begin() + static_cast<std::ptrdiff_t>(first[list_index++]);
            destination.assign(begin, begin + static_cast<std::ptrdiff_t>(records.items.size()));
            move_to_destinations(destination, [&](std::uint32_t i, std::uint32_t j) { records.swap(i, j); });
        };
        std::apply([&](auto&... list) { (permute(list), ...); }, out.primitives.of_type);
    }

    // Moves the record at each place i to destination[i], in place along the permutation's cycles (a moved
    // copy would add its whole size to the peak of compiling); uses destination up.
    template <typename Swap>
    static void move_to_destinations(LargeArray<std::uint32_t>& destination, Swap&& swap) {
        for (std::uint32_t i = 0; i < destination.size(); ++i) {
            while (destination[i] != i) {
                std::uint32_t j = destination[i];
                swap(i, j);
                std::swap(destination[i], destination[j]);
            }
        }
    }

    // Its triangles to the triangle list (and their corners, where some mesh is smooth) and, where there is one, to
    // the BVH's inputs.
    static void add_mesh(CompiledScene& out, const scene::Mesh& mesh, bool with_corners,
                         LargeArray<BvhInput>* bounded) {
        const scene::MeshData& data = *mesh.data;
        CompiledMesh compiled;
        if (data.smooth) {
            for (const scene::Vec3& normal : data.normals) {
                compiled.normals.push_back(Vec3(normal));
            }
        }
        out.meshes.push_back(std::move(compiled));
        TriangleList& triangles = out.triangles;
        const std::size_t live = data.triangles.size() - data.degenerate.size();
        triangles.items.reserve(triangles.items.size() + live);
        if (with_corners) {
            triangles.corners.reserve(triangles.corners.size() + live);
        }
        scene::for_each_live_triangle(data, [&](std::uint32_t i) {
            if (bounded != nullptr) {
                bounded->emplace_back(scene::bounds(data, data.triangles[i]),
                                      BvhItem{triangle_list, static_cast<std::uint32_t>(triangles.items.size())});
            }
            triangles.items.push_back(make_triangle(data, i, mesh.leaf));
            if (with_corners) {
                triangles.corners.push_back(data.triangles[i]);
            }
        });
    }

    // The instances, in file order, as the BVH's items name them; the brute-force list when there is no BVH.
    void add_instances(CompiledScene& out, std::size_t count) const {
        out.instances.reserve(count);
        for (const scene::Mesh& mesh : scene_.meshes) {
            if (!mesh.placement) {
                continue;
            }
            const scene::Transform to_world = mesh.placement->transform();
            out.instances.push_back(InstanceRecord::of(to_world, static_cast<std::size_t>(mesh.placement->shape),
                                                       mesh.leaf, mesh.material));
        }
    }

    // The instances' boxes in the order a walk meets them: the BVH's leaves, whose items then name their boxes, or
    // without one the records' own.
    static void add_instance_boxes(CompiledScene& out) {
        out.instance_boxes.reserve(out.instances.size());
        if (out.bvh.empty()) {
            for (std::uint32_t record = 0; record < out.instances.size(); ++record) {
                out.instance_boxes.push_back(instance_box(out, record));
            }
            return;
        }
        for (BvhItem& item : out.bvh.items) {
            if (item.list == instance_list) {
                out.instance_boxes.push_back(instance_box(out, item.index));
                item.index = static_cast<std::uint32_t>(out.instance_boxes.size() - 1);
            }
        }
    }

    // A shape's triangles in its own space, with its own BVH where brute force would cost more (as the scene's), its
    // records then in the order of that BVH's leaves.
    CompiledShape compile_shape(const scene::MeshData& data, const scene::Bounds& box) const {
        CompiledShape shape;
        const scene::Vec3 center = (box.low + box.high) * 0.5;
        const Vec3 rounded_center(center);
        Vec3 half_extent;
        for (int axis = 0; axis < 3; ++axis) {
            half_extent[axis] =
                math::rounded_up<float>((box.high[axis] - box.low[axis]) * 0.5 +
                                        std::abs(center[axis] - static_cast<double>(rounded_center[axis])));
        }
        shape.center = {rounded_center.x, rounded_center.y, rounded_center.z, 0.0f};
        shape.half_extent = {half_extent.x, half_extent.y, half_extent.z, 0.0f};
        if (data.smooth) {
            for (const scene::Vec3& normal : data.normals) {
                shape.mesh.normals.push_back(Vec3(normal));
            }
        }
        LargeArray<BvhInput> inputs;
        TriangleList in_file_order;
        scene::for_each_live_triangle(data, [&](std::uint32_t i) {
            inputs.push_back({scene::bounds(data, data.triangles[i]),
                              {triangle_list, static_cast<std::uint32_t>(in_file_order.items.size())}});
            in_file_order.items.push_back(make_triangle(data, i, -1));
            if (data.smooth) {
                in_file_order.corners.push_back(data.triangles[i]);
            }
        });
        const double cost = triangle_test_cost * static_cast<double>(in_file_order.items.size());
        if (accel_ == Accel::none || (accel_ == Accel::automatic && cost <= static_cast<double>(bvh_crossover))) {
            shape.triangles = std::move(in_file_order);
        } else {
            shape.bvh = build_bvh(std::move(inputs), triangle_bvh_costs);
            const LargeArray<BvhItem> items = std::move(shape.bvh.items);  // a leaf's triangles go to its places
            for (BvhNode& node : shape.bvh.nodes) {
                for (int c = 0; c < 4; ++c) {
                    const std::uint32_t count = node.count[c];
                    if (count == 0 || count == BvhNode::empty_child) {
                        continue;
                    }
                    const std::uint32_t first = node.first[c];
                    node.first[c] = static_cast<std::uint32_t>(shape.triangles.items.size());
                    for (std::uint32_t k = 0; k < (count + 3) / 4 * 4; ++k) {
                        const std::uint32_t index = items[first + std::min(k, count - 1)].index;
                        shape.triangles.items.push_back(in_file_order.items[index]);
                        if (data.smooth) {
                            shape.triangles.corners.push_back(in_file_order.corners[index]);
                        }
                    }
                }
            }
            for (std::size_t place = 0; place < shape.triangles.items.size(); place += 4) {
                const TriangleRecord* four[4];
                for (std::size_t k = 0; k < 4; ++k) {
                    four[k] = &shape.triangles.items[place + k];
                }
                shape.blocks.push_back(block_of(four));
            }
        }
        shape.frames.reserve(shape.triangles.items.size());
        for (const TriangleRecord& triangle : shape.triangles.items) {
            shape.frames.push_back(frame_of(triangle));
        }
        return shape;
    }

    // What brute force spends on one instance of the shape beyond the trip into its space: its triangles, or with a
    // BVH of its own at least what brute force spends where a BVH starts to pay.
    static double shape_cost(const CompiledShape& shape) {
        return shape.bvh.empty() ? triangle_test_cost * static_cast<double>(shape.triangles.items.size())
                                 : static_cast<double>(bvh_crossover);
    }

    float transmission_of(const scene::Object& object) const {
        return static_cast<float>(scene_.materials[static_cast<std::size_t>(object.material)].transmission);
    }

    // Nodes are laid out so that a node's children are contiguous in children_of. `apart`: where the leaves whose
    // records do not give back their surfaces go, for the leaf table; null for a solid shape, whose parts' surfaces
    // compile_solid makes.
    int add_csg_node(CsgTree& tree, const scene::Csg& csg, std::vector<LeafApart>* apart) {
        int index = static_cast<int>(tree.nodes.size());
        tree.nodes.push_back({csg.op, 0, static_cast<int>(csg.children.size()), -1});
        std::vector<int> children;
        for (const scene::Object& child : csg.children) {
            if (const auto* inner = std::get_if<scene::Csg>(&child.shape)) {
                children.push_back(add_csg_node(tree, *inner, apart));
            } else {
                int slot = static_cast<int>(tree.slot_leaf.size());
                tree.slot_leaf.push_back(child.leaf);
                // A CSG leaf's transmission is read from its material at each crossing, never from its list.
                add_primitive(tree.leaves, child, slot, 0.0f, apart);
                children.push_back(static_cast<int>(tree.nodes.size()));
                tree.nodes.push_back({scene::CsgOp::union_, 0, 0, slot});
            }
        }
        tree.nodes[static_cast<std::size_t>(index)].first_child = static_cast<int>(tree.children_of.size());
        tree.children_of.insert(tree.children_of.end(), children.begin(), children.end());
        tree.uses_inverse_direction = tree.leaves.any_uses_inverse_direction();
        return index;
    }

    // A CSG object of `tree` within `bounds` (in the world, made safe for float), added to out.csg_objects as `item`;
    // returns the bounds the BVH is to hold.
    static scene::Bounds add_csg_object(CompiledScene& out, std::shared_ptr<const CsgTree> tree,
                                        const scene::Bounds& bounds, std::int32_t instance, BvhItem& item) {
        const scene::Box bound = as_float_safe_box(bounds);
        item = {csg_list, static_cast<std::uint32_t>(out.csg_objects.size())};
        out.csg_objects.push_back({std::move(tree), make_shape(bound), instance});
        return {bound.min, bound.max};
    }

    // A solid shape in its own space: its tree (slots naming parts) and each part's surface and material.
    CompiledSolid compile_solid(const scene::SolidShape& shape) {
        auto tree = std::make_shared<CsgTree>();
        add_csg_node(*tree, std::get<scene::Csg>(shape.tree.shape), nullptr);
        CompiledSolid solid{std::move(tree), std::vector<Leaf>(shape.part_paths.size())};
        add_part_surfaces(shape.tree, solid.parts);
        return solid;
    }

    static void add_part_surfaces(const scene::Object& object, std::vector<Leaf>& parts) {
        std::visit(
            [&](const auto& shape) {
                using S = std::decay_t<decltype(shape)>;
                if constexpr (scene::is_primitive<S>) {
                    parts[static_cast<std::size_t>(object.leaf)] = {make_surface(shape), object.material};
                } else {
                    for (const scene::Object& child : shape.children) {
                        add_part_surfaces(child, parts);
                    }
                }
            },
            object.shape);
    }

    scene::Vec3 origin_;
    // The scene moved by −origin_ where the origin is not the world's; there the scene as it is, not a copy (at a
    // million instances a copy is a quarter of a gigabyte).
    std::optional<scene::Scene> moved_;
    const scene::Scene& scene_;
    Accel accel_;
    scene::Scene* given_up_;  // compile()'s
    std::vector<LeafApart> apart_;
};

}  // namespace

// Each primitive's float error is u times its coordinates relative to the origin. Relative to the eye those
// are the distances from the camera, small for a scene far from the world's origin (a scene 1e7 away loses
// nothing). A scene around the world's origin seen from far away (a telephoto view) has smaller
// coordinates where it is: it stays there, and compiles exactly as without re-basing. Ties keep the
// world's origin.
scene::Vec3 origin_of(const scene::Scene& scene) {
    const scene::Vec3& eye = scene.camera.eye;
    double around_world_origin = 0, around_eye = 0;
    for (const scene::Object& object : scene.objects) {
        scene::Object seen_from_eye = object;
        scene::move(seen_from_eye, 1, -eye);
        around_world_origin = std::max(around_world_origin, scene::largest_coordinate(object));
        around_eye = std::max(around_eye, scene::largest_coordinate(seen_from_eye));
    }
    std::vector<double> shape_extents;  // each mesh shape's largest |coordinate| in its own space
    for (const scene::MeshShape& shape : scene.mesh_shapes) {
        const scene::Bounds box = scene::vertex_bounds(*shape.data);
        shape_extents.push_back(std::max(scene::largest_coordinate(box.low), scene::largest_coordinate(box.high)));
    }
    for (const scene::Mesh& mesh : scene.meshes) {
        if (mesh.placement) {
            const double reach = math::row_sum_norm(mesh.placement->linear) *
                                 shape_extents[static_cast<std::size_t>(mesh.placement->shape)];
            around_world_origin =
                std::max(around_world_origin, scene::largest_coordinate(mesh.placement->translation) + reach);
            around_eye = std::max(around_eye, scene::largest_coordinate(mesh.placement->translation - eye) + reach);
            continue;
        }
        around_world_origin = std::max(around_world_origin, scene::largest_coordinate(mesh));
        around_eye = std::max(around_eye, scene::largest_coordinate(scene::moved(mesh, 1, -eye)));
    }
    return around_eye < around_world_origin ? eye : scene::Vec3{0, 0, 0};
}

CompiledScene compile(const scene::Scene& scene, Accel accel, scene::Scene* given_up) {
    return Compiler(scene, accel, given_up).run();
}

// In registers: the rows of L, one load each, transposed into its columns, so that each axis's sum takes its products
// in the scalar dot product's order, (x + y) + z.
InstanceBox instance_box(const CompiledScene& scene, std::uint32_t record) {
    const InstanceRecord& instance = scene.instances[record];
    const CompiledShape& shape = scene.shapes[instance.shape];
    const math::Matrix3<float>& linear = instance.to_world.linear;
    // Each row's fourth lane is the record's next float; the transpose moves it to the fourth column, unused.
    __m128 x = _mm_loadu_ps(&linear.row[0].x), y = _mm_loadu_ps(&linear.row[1].x);
    __m128 z = _mm_loadu_ps(&linear.row[2].x), unused = _mm_setzero_ps();
    _MM_TRANSPOSE4_PS(x, y, z, unused);
    const __m128 sign = _mm_set1_ps(-0.0f);
    const __m128 c = shape.center.load(), h = shape.half_extent.load();
    const __m128 t = _mm_blend_ps(_mm_loadu_ps(&instance.to_world.translation.x), _mm_setzero_ps(), 8);
    const __m128 center =
        _mm_add_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(x, spread<0>(c).m), _mm_mul_ps(y, spread<1>(c).m)),
                              _mm_mul_ps(z, spread<2>(c).m)),
                   t);
    const __m128 half = _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_andnot_ps(sign, x), spread<0>(h).m),
                                              _mm_mul_ps(_mm_andnot_ps(sign, y), spread<1>(h).m)),
                                   _mm_mul_ps(_mm_andnot_ps(sign, z), spread<2>(h).m));
    const __m128 far = _mm_add_ps(_mm_andnot_ps(sign, center), half);
    const __m128 reach = _mm_max_ss(_mm_max_ss(far, _mm_movehl_ps(far, far)), _mm_shuffle_ps(far, far, 1));
    const __m128 pad =
        _mm_mul_ss(reach, _mm_set_ss(static_cast<float>(instance_box_padding(condition_of(instance.norms)))));
    const __m128 padded = _mm_add_ps(half, _mm_shuffle_ps(pad, pad, 0));
    // A shape reaching past float's range (a vertex at 1e290) has an infinite box, and ∞ − ∞ makes its instance's faces
    // NaN, which a box test then passes for brute force and drops for the BVH's ordering by entry: such a face is the
    // whole axis. maxps and minps give their second operand where either is NaN.
    const __m128 everywhere = _mm_set1_ps(std::numeric_limits<float>::infinity());
    alignas(16) float low[4], high[4];
    _mm_store_ps(low, _mm_max_ps(_mm_sub_ps(center, padded), _mm_sub_ps(_mm_setzero_ps(), everywhere)));
    _mm_store_ps(high, _mm_min_ps(_mm_add_ps(center, padded), everywhere));
    return {{low[0], low[1], low[2]}, {high[0], high[1], high[2]}, record};
}

}  // namespace twinray::sse
