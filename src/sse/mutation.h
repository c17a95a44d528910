// Deliberately wrong variants of the SSE tracer, for mutation testing (tests/mutants/, `ctest -L mutants`):
// a build that defines TWINRAY_MUTANT to one Mutant's number must fail the conformance suite, which proves
// the suite can fail. In every other build active_mutant is none and each `if constexpr (mutated<…>)` is
// compiled out: the shipped tracer's code and speed are those without the hooks.
#pragma once

#ifdef TWINRAY_MUTANT_FREE
#error "This file includes sse/mutation.h, so each mutant must compile it: list it in twinray_sse_mutable_sources"
#endif

namespace twinray::sse {

// The numbers are the build's TWINRAY_MUTANT; tests/mutants/CMakeLists.txt lists the names in this order.
enum class Mutant : int {
    none = 0,
    normal_faces_away,                    // the shading normal faces away from the ray
    spawn_offset_too_small,               // secondary rays start 2⁻²⁰ of the derived offset off the surface
    ties_to_later_object,                 // at equal t the later object wins
    no_reprojection,                      // hit points are not re-projected onto their primitive
    snell_ratio_inverted,                 // η = ior entering, 1/ior leaving
    shadow_transmission_ignored,          // shadow rays pass transparent surfaces unattenuated
    csg_union_intersection_swapped,       // union sweeps with "and", intersection with "or"
    camera_off_by_half_pixel,             // primary rays through pixel corners, not centres
    phong_exponent_off_by_one,            // max(0, R·L)^(phong_size + 1)
    box_slab_strict,                      // a box's span needs enter < exit, not ≤
    depth_limit_off_by_one,               // secondary rays traced while depth ≤ max_depth
    total_internal_reflection_lost,       // on total internal reflection the transmission is not reflected
    triangle_edge_ties_ignored,           // an edge function of exactly 0 misses (strict > and <, no tie rule)
    triangle_winding_flipped,             // a triangle's front is its clockwise side
    triangle_shear_dropped,               // triangles projected along the direction's largest axis, not the ray
    transformed_normal_through_matrix,    // a transformed primitive's or instance's normal goes through L
    transformed_normal_not_renormalized,  // ... and is not made unit again where the primitive's own is unit
    transform_order_swapped,              // a ray enters object space as L⁻¹·o − t, not L⁻¹·(o − t)
};

#ifndef TWINRAY_MUTANT
#define TWINRAY_MUTANT 0
#endif

inline constexpr Mutant active_mutant = static_cast<Mutant>(TWINRAY_MUTANT);

template <Mutant M>
inline constexpr bool mutated = active_mutant == M;

}  // namespace twinray::sse
