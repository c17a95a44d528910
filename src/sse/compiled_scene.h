// The scene as the SSE tracer sees it: one flat array of 4-wide blocks per primitive type (structure of
// arrays), so a ray loops only over the types a scene has; CSG objects apart, so scenes without CSG pay
// nothing for it. Built once per render; every block is 16-byte aligned, on the heap too (std::vector
// of an alignas(16) type uses C++17 aligned new).
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

struct alignas(16) IntLanes {
    std::int32_t value[4];
};

struct alignas(16) FloatLanes {
    float value[4];
};

// Blocks of one primitive type, filled four lanes at a time; unused lanes hold an empty primitive that
// no ray can hit. `ids` are global leaf indices at top level and slots within a CSG object.
template <typename Block>
struct BlockList {
    std::vector<Block> blocks;
    std::vector<IntLanes> ids;
    std::vector<FloatLanes> transmission;  // of each lane's material, for shadow rays
    int count = 0;
};

struct CsgNodeF {
    scene::CsgOp op;
    int first_child;  // index into CsgObject::children_of
    int child_count;
    int slot;  // >= 0: a leaf, its slot in the object's leaf spans; -1: an operation
};

struct CsgObject {
    BlockList<PlaneBlock> planes;
    BlockList<SphereBlock> spheres;
    BlockList<CylinderBlock> cylinders;
    BlockList<BoxBlock> boxes;
    std::vector<std::int32_t> slot_leaf;  // slot -> global leaf index
    std::vector<CsgNodeF> nodes;         // nodes[0] is the root
    std::vector<int> children_of;        // child node indices, grouped per node
};

enum class LeafKind : std::uint8_t { plane, sphere, cylinder, box };

// What the normal of a hit needs, per leaf (looked up once per hit, not per test).
struct LeafInfo {
    LeafKind kind;
    Vec3 position;   // sphere centre, cylinder base
    Vec3 direction;  // plane normal, cylinder axis
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
    BlockList<PlaneBlock> planes;
    BlockList<SphereBlock> spheres;
    BlockList<CylinderBlock> cylinders;
    BlockList<BoxBlock> boxes;
    std::vector<CsgObject> csg_objects;
    // One axis-aligned bound per CSG object (ids: its index in csg_objects; ±∞ where a half-space leaves
    // it unbounded), so a ray evaluates only the CSG objects it can meet.
    BlockList<BoxBlock> csg_bounds;

    std::vector<LeafInfo> leaves;
    std::vector<MaterialF> materials;
    std::vector<LightF> lights;
    Color background, ambient_light;
    int max_depth = 1;
    // Model only what the scene requires: without transparent materials a shadow ray stops at its first
    // blocker and no refracted ray is ever traced.
    bool any_transparency = false;
    bool any_box_test = false;  // boxes or CSG bounds: rays need their reciprocal direction

    Vec3 eye, forward, right, up;
    float half_width = 0;
};

CompiledScene compile(const scene::Scene& scene);

}  // namespace twinray::sse
