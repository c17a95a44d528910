// Triangles of a mesh against four rays: the watertight test of Woop, Benthin and Wald (JCGT 2013). Mirrors
// reference/triangle.h section by section: the record and its construction, the crossing, the surface at a
// hit. The reference decides hit or miss exactly; here each ray is carried into a frame where it is the +z
// axis (translate, permute, shear), every vertex once per ray, so that two triangles sharing an edge compute
// its edge function from the same two float vertices and get it bit for bit with the opposite sign: no ray
// passes between them, and none hits both.
#pragma once

#include "scene/geometry.h"
#include "sse/mutation.h"
#include "sse/span4.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

namespace twinray::sse {

// The three vertices in float, relative to the compiled scene's origin, and whose triangle they are (44 bytes):
// a BVH leaf's triangles are tested, and a hit named, from the record alone, with no index lookup. A vertex
// shared by several triangles is the same float in each.
// A triangle's test against a packet (the sheared watertight test, no early miss), relative to a sphere's: 6.2
// (relative_test_cost in span4.h), and brute force tests every triangle with every ray, culled by no tile.
constexpr double triangle_test_cost = 6.2;

struct TriangleRecord {
    Vec3 a, b, c;
    std::int32_t leaf;       // its mesh's leaf
    std::uint32_t triangle;  // its index in the mesh (scene::MeshData::triangles)
};

inline TriangleRecord make_triangle(const scene::MeshData& mesh, std::uint32_t triangle, std::int32_t leaf) {
    const std::array<std::uint32_t, 3>& corners = mesh.triangles[triangle];
    return {Vec3(mesh.vertices[corners[0]]), Vec3(mesh.vertices[corners[1]]), Vec3(mesh.vertices[corners[2]]), leaf,
            triangle};
}

// What a hit's surface needs of the triangle alone, in its own space: its unit normal, n = (b − a) × (c − a) over
// |n|, and its longest edge, which scales its rounding bounds (scene::surface_bounds_of_triangle). The same float
// expressions as triangle_surfaces' lanes.
struct TriangleFrame {
    Vec3 normal;
    float longest_edge;
};

inline TriangleFrame frame_of(const TriangleRecord& t) {
    auto length = [](Vec3 v) { return std::sqrt(math::dot(v, v)); };
    Vec3 n = math::cross(t.b - t.a, t.c - t.a);
    return {n / length(n), std::max(length(t.b - t.a), std::max(length(t.c - t.b), length(t.a - t.c)))};
}

// What the test needs of each ray, once per packet: its origin, the axis kz of its direction's largest
// |component| (then kx, ky follow cyclically, a right-handed frame) and the shear that makes the direction
// (0, 0, 1): x' = x_kx − Sx·x_kz, y' = x_ky − Sy·x_kz, z' = Sz·x_kz.
struct ShearedRays {
    Vec3x4 origin, direction;  // as given, for the Möller–Trumbore knob
    Vec3x4 permuted_origin;    // (o_kx, o_ky, o_kz) per lane
    vbool4 kz_is_x, kz_is_y;   // else z
    vfloat4 shear_x, shear_y, shear_z;
    vbool4 towards_positive_kz;  // d_kz > 0: the frame's +z is the ray's direction, not its reverse
    // Where the four lanes share kz (primary and shadow rays nearly always do), a vertex is permuted once for
    // all of them, not lane by lane: kx, ky, kz of all lanes, else common_kz = -1.
    int common_kx = 0, common_ky = 0, common_kz = -1;

    // A packet's frame: one division per packet, made only for scenes with triangles.
    template <typename P>
    static ShearedRays of(const RayPacket& rays) {
        ShearedRays out;
        out.origin = rays.origin;
        out.direction = rays.direction;
        Vec3x4 size = abs(rays.direction);
        out.kz_is_x = (size.x >= size.y) & (size.x >= size.z);
        out.kz_is_y = !out.kz_is_x & (size.y >= size.z);
        out.permuted_origin = out.permute(rays.origin);
        Vec3x4 d = out.permute(rays.direction);
        vfloat4 inverse_z = divide<P>(vfloat4(1.0f), d.z);
        out.shear_x = d.x * inverse_z;
        out.shear_y = d.y * inverse_z;
        out.shear_z = inverse_z;
        if constexpr (mutated<Mutant::triangle_shear_dropped>) {
            out.shear_x = out.shear_y = vfloat4(0.0f);
        }
        out.towards_positive_kz = d.z > vfloat4(0.0f);
        int x_lanes = movemask(out.kz_is_x), y_lanes = movemask(out.kz_is_y);
        out.common_kz = x_lanes == 0xf ? 0 : y_lanes == 0xf ? 1 : (x_lanes | y_lanes) == 0 ? 2 : -1;
        out.common_kx = (out.common_kz + 1) % 3;
        out.common_ky = (out.common_kz + 2) % 3;
        return out;
    }

    // (x_kx, x_ky, x_kz) per lane.
    Vec3x4 permute(const Vec3x4& v) const {
        return {select(kz_is_x, v.y, select(kz_is_y, v.z, v.x)), select(kz_is_x, v.z, select(kz_is_y, v.x, v.y)),
                select(kz_is_x, v.x, select(kz_is_y, v.y, v.z))};
    }

    // A vertex in each ray's frame. Permuting before subtracting the origin rounds as after: a permutation
    // only chooses which components meet.
    TWINRAY_KERNEL Vec3x4 transformed(const Vec3& vertex) const {
        return in_frame(common_kz >= 0
                            ? Vec3x4{vfloat4(vertex[common_kx]), vfloat4(vertex[common_ky]), vfloat4(vertex[common_kz])}
                            : permute(broadcast(vertex)));
    }

    // (x_kx, x_ky, x_kz) where the four lanes share kz (common_kz >= 0): a choice of registers, no blend.
    TWINRAY_KERNEL Vec3x4 permute_alike(const Vec3x4& v) const {
        return common_kz == 0 ? Vec3x4{v.y, v.z, v.x} : common_kz == 1 ? Vec3x4{v.z, v.x, v.y} : v;
    }

    // Permuted points, lane by lane, translated and sheared into the frame.
    TWINRAY_KERNEL Vec3x4 in_frame(const Vec3x4& permuted) const {
        Vec3x4 p = permuted - permuted_origin;
        return {p.x - shear_x * p.z, p.y - shear_y * p.z, shear_z * p.z};
    }

    // Lane `lane`'s frame in all four lanes: to test that ray alone against four triangles at once
    // (crossing_of_four), each pair by the very arithmetic the packet's kernel gives that lane.
    ShearedRays lane_alone(int lane) const {
        auto one = [lane](vfloat4 v) { return vfloat4(v.lane(lane)); };
        auto one_mask = [lane](vbool4 m) { return ((movemask(m) >> lane) & 1) != 0 ? all_true() : none_true(); };
        auto one_vector = [&](const Vec3x4& v) { return Vec3x4{one(v.x), one(v.y), one(v.z)}; };
        ShearedRays out;
        out.origin = one_vector(origin);
        out.direction = one_vector(direction);
        out.permuted_origin = one_vector(permuted_origin);
        out.kz_is_x = one_mask(kz_is_x);
        out.kz_is_y = one_mask(kz_is_y);
        out.shear_x = one(shear_x);
        out.shear_y = one(shear_y);
        out.shear_z = one(shear_z);
        out.towards_positive_kz = one_mask(towards_positive_kz);
        out.common_kz = any(out.kz_is_x) ? 0 : any(out.kz_is_y) ? 1 : 2;
        out.common_kx = (out.common_kz + 1) % 3;
        out.common_ky = (out.common_kz + 2) % 3;
        return out;
    }
};

// Per lane: whether the ray meets the triangle at t > 0, t, and whether it meets the front.
struct TriangleHit4 {
    vbool4 valid;
    vfloat4 t;
    vbool4 front;
};

// The edge function of edge p → q at the frame's origin (the ray), F = q_x·p_y − q_y·p_x, as Woop's U, V, W.
// Where it is exactly 0 (the ray through the edge's line in float), its sign is that of the origin moved by
// (ε, ε²): F + ε·(q_y − p_y) + ε²·(p_x − q_x). The same rule for every triangle is one consistent
// perturbation of the ray, so an edge or a vertex hit exactly goes to exactly one of the triangles around
// it; it depends on p and q alone and changes sign with them, so the neighbour across the edge sees the
// opposite sign. Returned as two masks: positive, negative (both false: the edge is a point in the frame).
struct EdgeSign {
    vbool4 positive, negative;
};

inline EdgeSign edge_sign(vfloat4 value, const Vec3x4& p, const Vec3x4& q) {
    vfloat4 zero(0.0f);
    vbool4 on_line = value == zero;
    vfloat4 first = q.y - p.y;
    vfloat4 second = p.x - q.x;
    vbool4 tie_positive = (first > zero) | ((first == zero) & (second > zero));
    vbool4 tie_negative = (first < zero) | ((first == zero) & (second < zero));
    return {(value > zero) | (on_line & tie_positive), (value < zero) | (on_line & tie_negative)};
}

// Hit where the three edge signs agree (both faces: no back-face culling); det = U + V + W is then of their
// sign and non-zero. t = (U·a_z + V·b_z + W·c_z) / det, divided only once some lane hits. The ray meets the
// front (counter-clockwise side) where det has the sign of d_kz: det is the sheared frame's signed area,
// −(n·d)/d_kz with n = (b − a) × (c − a).
template <typename P>
TWINRAY_KERNEL TriangleHit4 crossing_in_frame(const Vec3x4& a, const Vec3x4& b, const Vec3x4& c,
                                              vbool4 towards_positive_kz) {
    vfloat4 u = c.x * b.y - c.y * b.x;
    vfloat4 v = a.x * c.y - a.y * c.x;
    vfloat4 w = b.x * a.y - b.y * a.x;
    vfloat4 zero(0.0f);
    TriangleHit4 hit;
    vbool4 all_positive = (u > zero) & (v > zero) & (w > zero);
    vbool4 all_negative = (u < zero) & (v < zero) & (w < zero);
    if constexpr (mutated<Mutant::triangle_edge_ties_ignored>) {
        hit.valid = all_positive | all_negative;
    } else {
        vbool4 some_zero = (u == zero) | (v == zero) | (w == zero);
        if (any(some_zero)) [[unlikely]] {
            EdgeSign su = edge_sign(u, b, c), sv = edge_sign(v, c, a), sw = edge_sign(w, a, b);
            all_positive = su.positive & sv.positive & sw.positive;
            all_negative = su.negative & sv.negative & sw.negative;
        }
        hit.valid = all_positive | all_negative;
    }
    if (none(hit.valid)) {
        return hit;
    }
    vfloat4 det = u + v + w;
    vfloat4 scaled_t = u * a.z + v * b.z + w * c.z;
    hit.t = divide<P>(scaled_t, det);
    hit.valid = hit.valid & (hit.t > zero) & (abs(hit.t) < vfloat4(infinity));
    vbool4 front = select_mask(all_positive, towards_positive_kz, !towards_positive_kz);
    hit.front = mutated<Mutant::triangle_winding_flipped> ? !front : front;
    return hit;
}

template <typename P>
TWINRAY_KERNEL TriangleHit4 crossing_of(const TriangleRecord& triangle, const ShearedRays& rays) {
    return crossing_in_frame<P>(rays.transformed(triangle.a), rays.transformed(triangle.b),
                                rays.transformed(triangle.c), rays.towards_positive_kz);
}

// One vertex of four triangle records, lane i records[i]'s. Each record is read 16 bytes at a time: the vertex and
// the 4 bytes after it, which are the record's own (its next vertex, or its leaf).
TWINRAY_KERNEL Vec3x4 vertex_of_four(const TriangleRecord* const records[4], Vec3 TriangleRecord::*vertex) {
    const float* at[4] = {&(records[0]->*vertex).x, &(records[1]->*vertex).x, &(records[2]->*vertex).x,
                          &(records[3]->*vertex).x};
    const Transposed4 columns = load_transposed(at);
    return {columns.column[0], columns.column[1], columns.column[2]};
}

// Four triangles side by side, lane i triangle i's: each vertex's x, y and z of the four (144 bytes), so that one ray's
// test of four (crossing_of_four) loads its vertices as they stand. Gathering them from four records took a quarter
// of that test's instructions.
struct alignas(16) TriangleBlock {
    float a[3][4], b[3][4], c[3][4];
};

inline TriangleBlock block_of(const TriangleRecord* const four[4]) {
    TriangleBlock block;
    for (int lane = 0; lane < 4; ++lane) {
        for (int axis = 0; axis < 3; ++axis) {
            block.a[axis][lane] = four[lane]->a[axis];
            block.b[axis][lane] = four[lane]->b[axis];
            block.c[axis][lane] = four[lane]->c[axis];
        }
    }
    return block;
}

// One ray (`alone`, ShearedRays::lane_alone) against four triangles, lane i against the block's triangle i: where a
// packet's lanes have parted, one test serves four triangles instead of one. The same edge functions, ties, t and
// front as crossing_of gives that ray's lane, bit for bit (tests/sse_test.cpp).
template <typename P>
TWINRAY_KERNEL TriangleHit4 crossing_of_four(const TriangleBlock& four, const ShearedRays& alone) {
    auto vertices = [&](const float(&vertex)[3][4]) {
        return alone.in_frame(
            alone.permute_alike({vfloat4::load(vertex[0]), vfloat4::load(vertex[1]), vfloat4::load(vertex[2])}));
    };
    return crossing_in_frame<P>(vertices(four.a), vertices(four.b), vertices(four.c), alone.towards_positive_kz);
}

// The precision knob `mt` (docs/performance.md): Möller and Trumbore's test (JGT 1997), the one most tracers
// ship: barycentrics from two cross products and one reciprocal of the determinant shared by the three
// numerators, each triangle's edges from its own vertices. Not watertight: a ray through the edge two
// triangles share gets each triangle's barycentric rounded its own way, so it may pass between them or hit
// both (its leak rate is measured by `twinray watertight` and in the bench's summary). Never the default.
template <typename P>
TWINRAY_KERNEL TriangleHit4 moller_trumbore_crossing(const TriangleRecord& triangle, const ShearedRays& rays) {
    Vec3x4 edge1 = broadcast(triangle.b - triangle.a), edge2 = broadcast(triangle.c - triangle.a);
    Vec3x4 p = math::cross(rays.direction, edge2);
    vfloat4 det = dot<P>(edge1, p);
    vfloat4 inverse = reciprocal<P>(det);
    Vec3x4 s = rays.origin - broadcast(triangle.a);
    vfloat4 u = dot<P>(s, p) * inverse;
    Vec3x4 q = math::cross(s, edge1);
    vfloat4 v = dot<P>(rays.direction, q) * inverse;
    vfloat4 zero(0.0f), one(1.0f);
    TriangleHit4 hit;
    hit.t = dot<P>(edge2, q) * inverse;
    hit.valid =
        !(det == zero) & (u >= zero) & (v >= zero) & (u + v <= one) & (hit.t > zero) & (abs(hit.t) < vfloat4(infinity));
    // det = edge1·(d × edge2) = −d·n with n = edge1 × edge2: positive where the ray meets the front.
    hit.front = det > zero;
    return hit;
}

// The triangle test the precision policy chooses: the watertight one, or Möller–Trumbore for the `mt` knob.
template <typename P>
TWINRAY_KERNEL TriangleHit4 triangle_crossing(const TriangleRecord& triangle, const ShearedRays& rays) {
    if constexpr (P::moller_trumbore) {
        return moller_trumbore_crossing<P>(triangle, rays);
    } else {
        return crossing_of<P>(triangle, rays);
    }
}

}  // namespace twinray::sse
