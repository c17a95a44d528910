// The scene as the SSE tracer sees it: one flat array per primitive type, so a packet loops only over
// the types a scene has; CSG objects apart (and culled by a bound), so scenes without CSG pay nothing
// for it. Built once per render. Every primitive record is 16-byte aligned, on the heap too
// (std::vector of an alignas(16) type uses C++17 aligned new).
#pragma once

#include "sse/box.h"
#include "sse/csg.h"
#include "sse/cylinder.h"
#include "sse/plane.h"
#include "sse/sphere.h"
#include "sse/tracer.h"

#include <cstdint>
#include <vector>

namespace twinray::sse {

// Primitives of one type. `ids` are global leaf indices at top level and slots within a CSG object;
// `transmission` is that of each primitive's material, for shadow rays.
// `bound_centers`/`bound_radii` are a sphere around each primitive (radius +∞ for planes), for
// culling whole tiles of primary rays.
template <typename Primitive>
struct PrimitiveList {
    std::vector<Primitive> items;
    std::vector<std::int32_t> ids;
    std::vector<float> transmission;
    std::vector<scene::Vec3> bound_centers;
    std::vector<double> bound_radii;

    void clear() {
        items.clear();
        ids.clear();
        transmission.clear();
        bound_centers.clear();
        bound_radii.clear();
    }
    void push_back_from(const PrimitiveList& other, std::size_t i) {
        items.push_back(other.items[i]);
        ids.push_back(other.ids[i]);
        transmission.push_back(other.transmission[i]);
        bound_centers.push_back(other.bound_centers[i]);
        bound_radii.push_back(other.bound_radii[i]);
    }
};

struct PrimitiveLists {
    PrimitiveList<PlaneF> planes;
    PrimitiveList<SphereF> spheres;
    PrimitiveList<CylinderF> cylinders;
    PrimitiveList<BoxF> boxes;
};

struct CsgNodeF {
    scene::CsgOp op;
    int first_child;  // index into CsgObject::children_of
    int child_count;
    int slot;  // >= 0: a leaf, its slot in the object's leaf spans; -1: an operation
};

struct CsgObject {
    PrimitiveLists leaves;                // ids are slots
    std::vector<std::int32_t> slot_leaf;  // slot -> global leaf index
    std::vector<CsgNodeF> nodes;          // nodes[0] is the root
    std::vector<int> children_of;         // child node indices, grouped per node
    BoxF bound;                           // axis-aligned, ±∞ where a half-space leaves it unbounded
};

enum class LeafKind : std::uint8_t { plane, sphere, cylinder, box };

// What the normal of a hit and its re-projection onto the surface need, per leaf (looked up once per
// hit, not per test).
struct LeafInfo {
    LeafKind kind;
    Vec3 position;    // sphere centre, cylinder base, box min corner
    Vec3 direction;   // plane normal, cylinder axis
    Vec3 far_corner;  // box max corner
    float radius;     // sphere, cylinder
    float height;     // cylinder
    float offset;     // plane
    int material;
};

struct MaterialF {
    Color color;
    float ambient, diffuse, phong, phong_size, reflection, transmission, ior;
};

struct LightF {
    Vec3 position;
    Color color;
};

struct CompiledScene {
    PrimitiveLists primitives;  // top-level primitives; ids are leaf indices
    std::vector<CsgObject> csg_objects;

    std::vector<LeafInfo> leaves;
    std::vector<MaterialF> materials;
    std::vector<LightF> lights;
    Color background, ambient_light;
    int max_depth = 1;
    // Model only what the scene requires: without transparent materials a shadow ray stops at its first
    // blocker and no refracted ray is ever traced; without boxes no ray computes its reciprocal.
    bool any_transparency = false;
    bool any_box_test = false;  // boxes, in CSG too, or CSG bounds

    Vec3 eye, forward, right, up;
    float half_width = 0;
};

CompiledScene compile(const scene::Scene& scene);

}  // namespace twinray::sse
