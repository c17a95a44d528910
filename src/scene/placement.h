// Placing primitives and meshes by a transform (docs/scene-format.md, "Transforms"): the transforms a scene
// composes, and what a primitive becomes under one. Where a primitive of the same kind can express the placed
// one, the loader computes it in double (a sphere moved, turned and scaled evenly is a sphere); only the rest
// stay in object space, as scene::Transformed.
#pragma once

#include "scene/scene.h"

namespace twinray::scene {

using Matrix3 = math::Matrix3<double>;

Transform identity_transform();
bool is_identity(const Transform& transform);
Transform translation(const Vec3& offset);
// Factors non-zero; a negative one mirrors.
Transform scaling(const Vec3& factors);
// By `degrees` about the unit `axis`, counter-clockwise looking down the axis towards the origin (right-handed).
// At a multiple of 90° about a coordinate axis every entry is exactly 0 or ±1: cos(π/2) is not 0 in double, so
// those angles are taken apart.
Transform rotation(const Vec3& axis, double degrees);
// About x, then y, then z.
Transform rotation_xyz(const Vec3& degrees);
// L and t as a 3 × 4 matrix gives them; L invertible.
Transform affine(const Matrix3& linear, const Vec3& offset);
// What an instance of shape `shape` holds of its transform (scene.h).
inline Placement placement_of(const Transform& to_world, int shape) {
    return {to_world.linear, to_world.translation, shape};
}
// κ_F(L) = ‖L‖_F·‖L⁻¹‖_F (≥ the 2-norm condition number, at most 3 times it); +∞ for a singular L.
double condition_number(const Transform& transform);

// The primitive placed in the world by `to_world`: of its own kind where that kind holds it exactly up to one
// rounding in double per coordinate (a plane under any transform; a sphere or cylinder under a similarity; a
// box under axis permutations and scales), else Transformed. A Transformed primitive composes with it.
Shape placed(const Shape& primitive, const Transform& to_world);
// Vertices and vertex normals (through the inverse transpose) placed in the world. Under a mirroring transform
// (negative determinant) each triangle's counter-clockwise side, its front, turns with them.
void place(MeshData& mesh, const Transform& to_world);
// The scene with every instance of a mesh shape replaced by the shape's mesh placed in world coordinates (its leaf,
// path and material kept): what the instancing benchmark measures instances against.
Scene flattened(const Scene& scene);

}  // namespace twinray::scene
