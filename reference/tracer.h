// The reference Whitted tracer: scalar, textbook formulas, a template on the scalar type.
// Tracer<double> is the oracle everything else is measured against; Tracer<float> runs the very same
// code in single precision, isolating the cost of precision from the cost of SIMD.
#pragma once

#include "math/camera.h"
#include "reference/box.h"
#include "reference/bvh.h"
#include "reference/cylinder.h"
#include "reference/external.h"
#include "reference/plane.h"
#include "reference/ray.h"
#include "reference/sphere.h"
#include "reference/transformed.h"
#include "reference/triangle.h"
#include "render/ray_tree.h"
#include "render/render.h"
#include "scene/depth_control.h"
#include "scene/scene.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <utility>
#include <variant>
#include <vector>

namespace twinray::reference {

// Each primitive's shape is what its make_shape returns (sphere.h, plane.h, ...): the variants follow the
// one list of primitive types (scene::PrimitiveTypes).
template <typename T>
struct ShapeFor {
    template <typename S>
    using of = decltype(make_shape<T>(std::declval<const S&>(), 0));
};

template <typename T>
using PrimitiveShapes = scene::PrimitiveTypes::map<ShapeFor<T>::template of>;

template <typename T>
using PrimitiveShape = typename PrimitiveShapes<T>::template apply<std::variant>;

template <typename T>
struct CsgNode;
template <typename T>
struct PlacedSolid;

template <typename T>
using Shape = typename PrimitiveShapes<T>::template append<CsgNode<T>, PlacedSolid<T>>::template apply<std::variant>;

template <typename T>
struct CsgNode {
    scene::CsgOp op = scene::CsgOp::union_;
    std::vector<Shape<T>> children;
};

// A solid shape (scene::SolidShape) compiled once in its own space, its parts numbered as leaves there: the tree, each
// part's primitive by number (where its hits are re-projected) and material (-1: the instance's).
template <typename T>
struct SolidShape {
    Shape<T> tree;
    std::vector<PrimitiveShape<T>> parts;
    std::vector<int> part_materials;
};

// An instance of a solid shape, tested as any top-level object: the world ray carried into the shape's space
// (unit_object_ray), the shape's spans found there and carried back, each crossing naming the instance's leaf and
// the part.
template <typename T>
struct PlacedSolid {
    std::shared_ptr<const SolidShape<T>> shape;
    Instance<T> instance;
    int material = 0;  // where a part names none
};

template <typename T>
struct Material {
    Color<T> color;
    T ambient, diffuse, phong, phong_size, reflection, transmission, ior;
};

template <typename T>
struct Light {
    Vec3<T> position;
    Color<T> color;
};

template <typename T>
class Tracer {
public:
    // With `external` (which must outlive the tracer), every ray's crossings are its (external.h); `accel` then
    // applies to the reference's own structures only, which place its hits on their surfaces.
    explicit Tracer(const scene::Scene& scene, Accel accel = Accel::automatic,
                    const ExternalIntersector<T>* external = nullptr);

    // The first surface along the ray with t > 0; a miss for a ray that is not is_traceable (ray.h).
    std::optional<Hit<T>> intersect(const Ray<T>& ray) const;

    // The colour the ray sees; `depth` is 1 for primary rays. The ray is one pixel's tree: it has the whole
    // ray budget (scene/depth_control.h). `tally`, if given, adds every ray this traces (this one, shadow
    // rays and secondary rays), the secondary rays the depth control left out and whether the budget ran
    // out. `tree`, if given, receives every ray traced, what it hit, each light's visibility, its colours
    // and the rays left out (twinray probe); the colour is the same with or without it. A ray that is not
    // is_traceable (ray.h) sees the background, and nothing is traced or recorded.
    Color<T> trace(const Ray<T>& ray, int depth, TraceTally* tally = nullptr, RayTree* tree = nullptr) const;

    // The ray through the centre of pixel (x, y) of a width × height image, (0, 0) top-left.
    Ray<T> primary_ray(int x, int y, int width, int height) const;

    // The share of the light's colour that reaches `origin` (already off the surface): the product of
    // the transmission of every surface crossed strictly before the light.
    T shadow_transmittance(Vec3<T> origin, Vec3<T> light_position) const;

    // How many mesh triangles the ray crosses with t in (0, distance): what the watertightness suite counts
    // (accuracy/watertight.h), 1 where a ray leaves a closed mesh once.
    int mesh_crossings(const Ray<T>& ray, T distance) const;

    // Where a secondary ray leaving `hit` towards `direction` starts: hit.spawn_offset off the surface.
    static Vec3<T> spawn_origin(const Hit<T>& hit, Vec3<T> direction);

    // What a hit names: a leaf, or on an instance of a solid shape its part.
    const Material<T>& material_of(int leaf, int part = -1) const { return materials_[material_index(leaf, part)]; }

private:
    // One pixel's tree as it is traced: rays counted, what the depth control left out, the recording.
    struct TreeWalk {
        std::uint64_t rays = 0;
        scene::PixelLedger ledger;
        RayTree* tree = nullptr;
    };

    int material_index(int leaf, int part) const;
    // The instance of a solid shape whose leaf this is.
    const PlacedSolid<T>& solid_instance(int leaf) const;

    // intersect() without the check of the ray: every ray the tracer makes itself is traceable.
    std::optional<Hit<T>> first_hit(const Ray<T>& ray) const;
    // first_hit() from the external intersector's nearest crossing.
    std::optional<Hit<T>> external_hit(const Ray<T>& ray) const;
    // Moves hit.point onto the surface of its primitive (`mesh` or `instance` where it is one of theirs), with its
    // spawn offset and, on a smooth mesh, its shading normal.
    void project_onto_surface(Hit<T>& hit, const MeshShape<T>* mesh, const Instance<T>* instance) const;
    // `transmittance` (the objects' product so far) times that of every mesh triangle the ray crosses before
    // `distance`.
    T meshes_transmittance(const Ray<T>& ray, T distance, T transmittance) const;
    // trace() of one ray of the tree, recorded (if walk.tree) as a `kind` child of node `parent`.
    Color<T> trace_ray(const Ray<T>& ray, int depth, const scene::RayShare& share, TreeWalk& walk, RayKind kind,
                       int parent) const;
    // `node`: this hit's ray in walk.tree, if recording.
    Color<T> shade(const Ray<T>& ray, const Hit<T>& hit, int depth, const scene::RayShare& share, TreeWalk& walk,
                   int node) const;
    // Whether the depth control traces the child ray `share` of node `parent`; recorded if not.
    bool admits(const scene::RayShare& share, int depth, TreeWalk& walk, RayKind kind, int parent) const;

    math::CameraBasis<T> camera_;
    Color<T> background_, ambient_light_;
    int max_depth_;
    scene::DepthControl depth_control_;
    std::vector<Material<T>> materials_;
    std::vector<int> leaf_materials_;
    std::vector<Light<T>> lights_;
    // The scene's objects in file order, then its instances of solid shapes in file order (from
    // first_solid_instance_ on, their leaves ascending).
    std::vector<Shape<T>> objects_;
    std::size_t first_solid_instance_ = 0;
    std::vector<PrimitiveShape<T>> leaf_shapes_;  // by leaf index: where hit points are re-projected
    ObjectBvh<T> bvh_;                            // empty: every ray tests every object
    // Tested by every ray after the objects, each through its own BVH; a mesh's leaf in leaf_shapes_ is unused.
    std::vector<MeshShape<T>> meshes_;
    // Instances of mesh shapes, tested after the meshes: each shape built once in its own space (leaf unused),
    // the instances in file order and found through instance_bvh_ unless the BVH is off.
    std::vector<MeshShape<T>> mesh_shapes_;
    std::vector<Instance<T>> instances_;
    ObjectBvh<T> instance_bvh_;
    const ExternalIntersector<T>* external_ = nullptr;

    // Calls visit(instance, object ray, crossing) for every triangle of every instance the ray meets with t in
    // (0, limit()], as for_each_crossing does (in no particular order).
    template <typename Limit, typename Visit>
    void for_each_instance_crossing(const Ray<T>& ray, Limit&& limit, Visit&& visit) const;

    // Calls visit(object) for the objects a ray may meet within [0, limit()]: every object, or with a BVH the
    // unbounded ones and those it finds (in no particular order).
    template <typename Limit, typename Visit>
    void for_each_candidate(const Ray<T>& ray, Limit&& limit, Visit&& visit) const;
};

// With `external`, every ray's crossings are its (external.h).
template <typename T>
RenderResult render(const scene::Scene& scene, const RenderOptions& options,
                    const ExternalIntersector<T>* external = nullptr);

// With a tracer built for `scene` (options.accel is not read).
template <typename T>
RenderResult render(const Tracer<T>& tracer, const scene::Scene& scene, const RenderOptions& options);

extern template class Tracer<double>;
extern template class Tracer<float>;
extern template RenderResult render<double>(const scene::Scene&, const RenderOptions&,
                                            const ExternalIntersector<double>*);
extern template RenderResult render<float>(const scene::Scene&, const RenderOptions&,
                                           const ExternalIntersector<float>*);
extern template RenderResult render<double>(const Tracer<double>&, const scene::Scene&, const RenderOptions&);
extern template RenderResult render<float>(const Tracer<float>&, const scene::Scene&, const RenderOptions&);

}  // namespace twinray::reference
