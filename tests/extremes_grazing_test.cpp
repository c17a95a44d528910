// Grazing and tangent rays (docs/numerics.md): families of rays whose closest approach to a sphere's or a
// cylinder's silhouette, a box edge or a CSG seam is (1 + δ)·size, with δ = ±2^-1 … ±2^-55, judged
// against the exact answer (long double, numerics::exact_span) for the ray and the primitive as the
// tracer holds them (rounded to float for the float tracers). Hit or miss, and which primitive, may flip
// only inside a band |δ| ≤ δ_band that the test states and prints; outside it t and the normal stay
// within their bounds.
#include "numerics/numerics.h"
#include "scene/geometry.h"
#include "tests/extremes.h"
#include "tests/scene_builder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace {

using twinray::test::unit_roundoff;

using twinray::Vec3d;
using twinray::numerics::ExactSpan;
using twinray::numerics::TracerKind;
namespace test = twinray::test;
namespace scene = twinray::scene;

using twinray::math::cross;
using twinray::math::dot;

Vec3d unit(Vec3d a) {
    return twinray::math::normalize_by_reciprocal(a);
}
double max_abs(Vec3d a) {
    return twinray::math::max_abs_component(a);
}

// The ray as the tracer receives it: rounded to float for the float tracers.
Vec3d as_held(Vec3d v, TracerKind kind) {
    if (kind == TracerKind::reference_double) {
        return v;
    }
    return twinray::scene::rounded_to_float(v);
}

struct Truth {
    bool hit = false;
    int leaf = -1;
    double t = 0;
    Vec3d normal{};
};

struct Crossing {
    long double t;
    int leaf;
};
struct Interval {
    Crossing enter, exit;
};

std::vector<Interval> intervals_of(const scene::Object& primitive, int leaf, Vec3d o, Vec3d d) {
    ExactSpan span = twinray::numerics::exact_span(primitive, o, d);
    if (!span.valid) {
        return {};
    }
    return {{{span.enter, leaf}, {span.exit, leaf}}};
}

// Two convex operands: each gives at most one interval.
std::vector<Interval> combine(scene::CsgOp op, const std::vector<Interval>& a, const std::vector<Interval>& b) {
    if (op == scene::CsgOp::union_) {
        if (a.empty() || b.empty())
            return a.empty() ? b : a;
        const Interval &x = a[0], &y = b[0];
        if (x.enter.t <= y.exit.t && y.enter.t <= x.exit.t) {
            return {{x.enter.t <= y.enter.t ? x.enter : y.enter, x.exit.t >= y.exit.t ? x.exit : y.exit}};
        }
        return x.enter.t < y.enter.t ? std::vector<Interval>{x, y} : std::vector<Interval>{y, x};
    }
    if (a.empty() || b.empty())
        return op == scene::CsgOp::difference ? a : std::vector<Interval>{};
    const Interval &x = a[0], &y = b[0];
    if (op == scene::CsgOp::intersection) {
        Interval both{x.enter.t >= y.enter.t ? x.enter : y.enter, x.exit.t <= y.exit.t ? x.exit : y.exit};
        return both.enter.t < both.exit.t ? std::vector<Interval>{both} : std::vector<Interval>{};
    }
    std::vector<Interval> pieces;
    if (y.enter.t > x.enter.t)
        pieces.push_back({x.enter, y.enter.t < x.exit.t ? y.enter : x.exit});
    if (y.exit.t < x.exit.t)
        pieces.push_back({y.exit.t > x.enter.t ? y.exit : x.enter, x.exit});
    std::vector<Interval> result;
    for (const Interval& piece : pieces) {
        if (piece.enter.t < piece.exit.t)
            result.push_back(piece);
    }
    return result;
}

// The exact first crossing with t > 0 of a scene holding one primitive or one CSG of two primitives.
Truth exact_first_hit(const scene::Scene& held, Vec3d o, Vec3d d) {
    std::vector<const scene::Object*> leaves = twinray::numerics::leaf_objects(held);
    const scene::Object& object = held.objects.front();
    std::vector<Interval> spans;
    if (const auto* csg = std::get_if<scene::Csg>(&object.shape)) {
        spans = combine(csg->op, intervals_of(csg->children[0], 0, o, d), intervals_of(csg->children[1], 1, o, d));
    } else {
        spans = intervals_of(object, 0, o, d);
    }
    for (const Interval& span : spans) {
        for (const Crossing& c : {span.enter, span.exit}) {
            if (c.t > 0 && std::isfinite(static_cast<double>(c.t))) {
                double t = static_cast<double>(c.t);
                return {true, c.leaf, t,
                        twinray::numerics::exact_normal(*leaves[static_cast<std::size_t>(c.leaf)], o + t * d)};
            }
        }
    }
    return {};
}

// One family of rays: the scene, and the ray (origin, unit direction) for each δ.
struct Family {
    std::string name;
    scene::Scene scene;
    double size;
    std::function<std::pair<Vec3d, Vec3d>(double)> ray;
};

std::vector<Family> families(double size, double shift) {
    Vec3d c{0.3 * size + shift, -0.2 * size + shift, 0.1 * size + shift};
    std::vector<Family> out;
    {
        test::SceneBuilder b;
        b.object(test::sphere(c, size));
        Vec3d d = unit({1, 0.3, 0.2});
        Vec3d e = unit(cross(d, {0.1, 0, 1}));
        out.push_back({"sphere silhouette", b.build(), size, [=](double delta) {
                           return std::pair{c - (4 * size) * d + (size * (1 + delta)) * e, d};
                       }});
    }
    {
        test::SceneBuilder b;
        Vec3d a = unit({0.2, 1, 0.1});
        b.object(test::cylinder(c - size * a, c + size * a, 0.5 * size));
        Vec3d d = unit(cross(a, {0, 0, 1}));
        Vec3d e = cross(a, d);
        out.push_back({"cylinder silhouette", b.build(), size, [=](double delta) {
                           return std::pair{c - (4 * size) * d + (0.5 * size * (1 + delta)) * e, d};
                       }});
    }
    {
        test::SceneBuilder b;
        b.object(test::box(c - size * Vec3d{1, 0.8, 0.6}, c + size * Vec3d{1, 0.8, 0.6}));
        Vec3d edge = c + size * Vec3d{1, 0.8, 0};
        Vec3d d = unit({-1, 1, 0.3});
        Vec3d e = unit({1, 1, 0});
        out.push_back({"box edge", b.build(), size, [=](double delta) {
                           return std::pair{edge - (4 * size) * d + (size * delta) * e, d};
                       }});
    }
    // The seam where the face x = max of a box meets a sphere of radius 1.3: a circle of radius √0.69 in
    // that face; the rays cross it along y.
    for (auto [op, name] :
         {std::pair{scene::CsgOp::union_, "union seam"}, std::pair{scene::CsgOp::intersection, "intersection seam"},
          std::pair{scene::CsgOp::difference, "difference seam"}}) {
        test::SceneBuilder b;
        b.object(test::csg(
            op, {test::box(c - size * Vec3d{1, 1, 1}, c + size * Vec3d{1, 1, 1}), test::sphere(c, 1.3 * size)}));
        Vec3d seam = c + size * Vec3d{1, std::sqrt(0.69), 0};
        Vec3d d = unit({-1, 0, 0.3});
        out.push_back({name, b.build(), size, [=](double delta) {
                           return std::pair{seam - (4 * size) * d + (size * delta) * Vec3d{0, 1, 0}, d};
                       }});
    }
    return out;
}

// δ_band = 16·u·(1 + shift/size): the ray's origin, 4 sizes from the object, and every coordinate are
// rounded by u·(|shift| + 5·size), and each formula rounds a few times more. Measured: at most 8·u.
double band(TracerKind kind, double size, double shift) {
    return 16 * unit_roundoff(kind) * (1 + shift / size);
}

class ExtremesGrazing : public twinray::test::EachTracer {};

// Outside the band, |Δt|·|cos θ| ≤ 4·u·S and the normal within 4·u·S/(size·|cos θ|) rad, S = |o|∞ + t +
// size: the float ray passes u·S from the exact one, a surface met at angle θ turns that into a shift
// along the ray of u·S/|cos θ|, and a curved surface's normal turns by that shift over its radius.
// Measured: at most 1.5·u·S for either.
TEST_P(ExtremesGrazing, HitOrMissFlipsOnlyInsideTheStatedBandAndTAndNormalsStayBoundedOutsideIt) {
    TracerKind kind = GetParam();
    double u = unit_roundoff(kind);
    for (auto [size, shift] : {std::pair{1.0, 0.0}, std::pair{1e-3, 0.0}, std::pair{1e4, 0.0}, std::pair{1.0, 1e3}}) {
        for (const Family& family : families(size, shift)) {
            scene::Scene held = twinray::numerics::held_geometry(family.scene, kind);
            auto tracer = twinray::numerics::make_tracer(family.scene, kind);
            double widest_disagreement = 0, worst_t = 0, worst_normal = 0;
            int rays = 0, hits = 0;
            for (int power = 1; power <= 55; ++power) {
                for (double sign : {-1.0, 1.0}) {
                    double delta = sign * std::ldexp(1.0, -power);
                    auto [origin, direction] = family.ray(delta);
                    Vec3d o = as_held(origin, kind), d = as_held(direction, kind);
                    twinray::numerics::FirstHit hit = tracer->intersect(o, d);
                    Truth truth = exact_first_hit(held, o, d);
                    ++rays;
                    ASSERT_TRUE(!hit.hit || (std::isfinite(hit.t) && std::isfinite(dot(hit.normal, hit.normal))))
                        << family.name << ": NaN or infinity in a hit at δ = " << delta;
                    if (hit.hit != truth.hit || (hit.hit && hit.leaf != truth.leaf)) {
                        widest_disagreement = std::max(widest_disagreement, std::fabs(delta));
                        continue;
                    }
                    if (!hit.hit || std::fabs(delta) <= band(kind, size, shift)) {
                        continue;
                    }
                    ++hits;
                    double cosine = std::fabs(dot(d, truth.normal));
                    double s = max_abs(o) + truth.t + family.size;
                    double t_error = std::fabs(hit.t - truth.t) * cosine / (4 * u * s);
                    Vec3d across = cross(hit.normal, truth.normal);
                    double angle = std::atan2(std::sqrt(dot(across, across)), std::fabs(dot(hit.normal, truth.normal)));
                    double normal_error = angle / (4 * u * s / (family.size * cosine));
                    EXPECT_LE(t_error, 1.0) << family.name << " (size " << size << ", shift " << shift
                                            << ") δ = " << delta << ": t " << hit.t << " against " << truth.t;
                    EXPECT_LE(normal_error, 1.0) << family.name << " (size " << size << ", shift " << shift
                                                 << ") δ = " << delta << ": normal off by " << angle << " rad";
                    worst_t = std::max(worst_t, t_error);
                    worst_normal = std::max(worst_normal, normal_error);
                }
            }
            EXPECT_LE(widest_disagreement, band(kind, size, shift))
                << family.name << " (size " << size << ", shift " << shift
                << "): hit/miss or primitive differs from the exact answer at |δ| = " << widest_disagreement;
            EXPECT_GE(hits, 5) << family.name;
            std::printf(
                "[ measured ] %-16s %-19s size %-6g shift %-5g: widest flip |δ| %.2e (band %.2e); outside: %d hits, "
                "t at most %.3f and normal %.3f of their bounds\n",
                twinray::numerics::tracer_name(kind), family.name.c_str(), size, shift, widest_disagreement,
                band(kind, size, shift), hits, worst_t, worst_normal);
        }
    }
}

TWINRAY_FOR_EACH_TRACER(ExtremesGrazing);

}  // namespace
