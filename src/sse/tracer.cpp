#include "sse/tracer.h"

#include "math/rounding.h"
#include "sse/camera.h"
#include "sse/shading.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

// Why packets of four rays (one ray per lane, each primitive broadcast) and not one ray against four
// primitives (one primitive per lane): both run the same intersection formulas, and we measured both
// (docs/performance.md). Testing one ray against four primitives left the lanes of small scenes half
// empty (complete1 has 2 planes, 4 spheres, 1 cylinder) and, above all, left shading scalar, and
// shading is most of a Whitted ray's work: normals, light vectors, shadow-ray set-up, Phong, Snell. With
// four rays per lane set, intersection, shadows and shading all run four-wide, and secondary rays
// continue as packets under a mask of the lanes that spawn them.

namespace twinray::sse {
namespace {

// A function, not a constant: no SSE code may run at start-up, before the CPU check.
vbool4 lane_0_only() {
    return vbool4{_mm_castsi128_ps(_mm_setr_epi32(-1, 0, 0, 0))};
}

// A world ray as the compiled scene holds it: its origin minus the scene's, subtracted in double and rounded
// once to float (exact for primary_ray's rays, whose origin is the compiled eye translated back).
struct RelativeRay {
    Vec3 origin;
    Vec3 direction;
};

RelativeRay relative_to(const CompiledScene& scene, const Ray& ray) {
    return {Vec3(ray.origin - scene.origin), ray.direction};
}

// The compiled scene's point p back in world coordinates: origin + p in double, one rounding of at most
// 2⁻⁵³·|origin + p| (far below the float point's own u·|p|).
Vec3d to_world(const CompiledScene& scene, const Vec3& point) {
    return scene.origin + Vec3d(point);
}

// A single ray through the packet path: all four lanes carry it, only lane 0 is active.
RayPacket single_ray_packet(const RelativeRay& ray) {
    return RayPacket(broadcast(ray.origin), broadcast(ray.direction), lane_0_only());
}

// Lane 0 of a packet's hit, in world coordinates.
Hit lane_0_hit(const CompiledScene& scene, const Hit4& hit4) {
    Hit hit;
    hit.t = hit4.t.lane(0);
    hit.point = to_world(scene, lane(hit4.point, 0));
    hit.normal = lane(hit4.normal, 0);
    alignas(16) std::int32_t lanes[4];
    hit4.leaf.store(lanes);
    hit.leaf = lanes[0];
    hit4.triangle.store(lanes);
    hit.triangle = lanes[0];
    hit4.part.store(lanes);
    hit.part = lanes[0];
    hit.shading_normal = lane(hit4.shading_normal, 0);
    hit.entering = (movemask(hit4.entering) & 1) != 0;
    hit.spawn_offset = hit4.spawn_offset.lane(0);
    return hit;
}

int knob_bits(const Precision& precision) {
    return (precision.fast_rcp ? 1 : 0) | (precision.fast_rsqrt ? 2 : 0) | (precision.dpps ? 4 : 0) |
           (precision.textbook_quadratic ? 8 : 0) | (precision.moller_trumbore ? 16 : 0);
}

// The kernels compiled in, one instantiation each: exact, each knob alone, and the three that buy speed
// together (rcp, rsqrt, textbook; dpps costs time in a packet tracer, docs/performance.md). Calls
// visit(policy) with the policy type of `precision`'s knobs; every other combination is refused.
template <typename Visit>
decltype(auto) with_precision_policy(const Precision& precision, Visit&& visit) {
    // A mutant (sse/mutation.h) is judged by the conformance suite, which runs the exact kernels: building
    // only those keeps twelve mutants cheap to compile.
    if constexpr (active_mutant != Mutant::none) {
        if (knob_bits(precision) != 0) {
            throw std::invalid_argument("a mutant SSE tracer is built for the exact kernels only");
        }
        return visit(ExactPrecision{});
    } else {
        switch (knob_bits(precision)) {
            case 0: return visit(ExactPrecision{});
            case 1: return visit(PrecisionPolicy<true, false, false, false>{});
            case 2: return visit(PrecisionPolicy<false, true, false, false>{});
            case 4: return visit(PrecisionPolicy<false, false, true, false>{});
            case 8: return visit(PrecisionPolicy<false, false, false, true>{});
            case 16: return visit(PrecisionPolicy<false, false, false, false, true>{});
            case 11: return visit(PrecisionPolicy<true, true, false, true>{});
            default:
                throw std::invalid_argument("the SSE tracer is not built for the knobs " + precision_name(precision) +
                                            "; built: " + built_precisions());
        }
    }
}

}  // namespace

bool precision_is_built(const Precision& precision) {
    int knobs = knob_bits(precision);
    return knobs == 0 || knobs == 1 || knobs == 2 || knobs == 4 || knobs == 8 || knobs == 16 || knobs == 11;
}

std::string built_precisions() {
    return "exact, rcp, rsqrt, dpps, textbook, mt, rcp+rsqrt+textbook (each also with ftz)";
}

std::vector<Precision> every_built_precision() {
    std::vector<Precision> built;
    for (int knobs = 0; knobs < 64; ++knobs) {
        Precision precision{(knobs & 1) != 0, (knobs & 2) != 0,  (knobs & 4) != 0,
                            (knobs & 8) != 0, (knobs & 16) != 0, (knobs & 32) != 0};
        if (precision_is_built(precision)) {
            built.push_back(precision);
        }
    }
    return built;
}

std::string precision_name(const Precision& precision) {
    std::string name;
    auto add = [&](bool on, const char* knob) {
        if (on) {
            name += (name.empty() ? "" : "+") + std::string(knob);
        }
    };
    add(precision.fast_rcp, "rcp");
    add(precision.fast_rsqrt, "rsqrt");
    add(precision.dpps, "dpps");
    add(precision.textbook_quadratic, "textbook");
    add(precision.moller_trumbore, "mt");
    add(precision.flush_denormals, "ftz");
    return name.empty() ? "exact" : name;
}

Tracer::Tracer(const scene::Scene& scene, const Precision& precision, Accel accel)
    : Tracer(std::make_unique<CompiledScene>(compile(scene, accel)), precision) {}

Tracer::Tracer(scene::Scene& scene, GiveUpGeometry, const Precision& precision, Accel accel)
    : Tracer(std::make_unique<CompiledScene>(compile(scene, accel, &scene)), precision) {}

Tracer::Tracer(std::unique_ptr<CompiledScene> compiled, const Precision& precision)
    : scene_(std::move(compiled)), precision_(precision) {
    with_precision_policy(precision, [](auto) {});  // refuses a combination that is not built
}

Tracer::~Tracer() = default;

BvhStats Tracer::bvh_stats() const {
    const Bvh& bvh = scene_->bvh;
    return {bvh.items.size(),           bvh.nodes.size(), bvh_bytes(bvh), scene_->bvh_build_cpu_seconds,
            scene_->brute_force_weight, scene_->crossover};
}

std::optional<Hit> Tracer::intersect(const Ray& world_ray) const {
    RelativeRay ray = relative_to(*scene_, world_ray);
    if (!math::is_traceable(ray.origin, ray.direction)) {
        return std::nullopt;
    }
    ScopedFlushDenormals denormals(precision_.flush_denormals);
    Hit4 hit4 = with_precision_policy(precision_, [&](auto policy) {
        RayPacket rays = single_ray_packet(ray);
        return PacketTracer<decltype(policy)>(*scene_).intersect(rays);
    });
    if (!(movemask(hit4.hit) & 1)) {
        return std::nullopt;
    }
    return lane_0_hit(*scene_, hit4);
}

std::vector<Hit> Tracer::hits_along(const Ray& world_ray, float distance) const {
    RelativeRay ray = relative_to(*scene_, world_ray);
    std::vector<Hit> hits;
    if (!math::is_traceable(ray.origin, ray.direction)) {
        return hits;
    }
    ScopedFlushDenormals denormals(precision_.flush_denormals);
    with_precision_policy(precision_, [&](auto policy) {
        RayPacket rays = single_ray_packet(ray);
        NearestHit<decltype(policy)>(*scene_).for_each_crossing(
            rays, distance, [&](const Hit4& hit4) { hits.push_back(lane_0_hit(*scene_, hit4)); });
    });
    return hits;
}

int Tracer::mesh_crossings(const Ray& ray, float distance) const {
    const std::vector<Hit> hits = hits_along(ray, distance);
    return static_cast<int>(std::count_if(hits.begin(), hits.end(), [](const Hit& hit) { return hit.triangle >= 0; }));
}

Color Tracer::trace(const Ray& world_ray, int depth, TraceTally* tally, RayTree* tree) const {
    RelativeRay ray = relative_to(*scene_, world_ray);
    if (!math::is_traceable(ray.origin, ray.direction)) {
        return scene_->background;
    }
    ScopedFlushDenormals denormals(precision_.flush_denormals);
    PacketWalk walk;
    walk.tree = tree;
    Vec3x4 color = with_precision_policy(precision_, [&](auto policy) {
        RayPacket packet = single_ray_packet(ray);
        return PacketTracer<decltype(policy)>(*scene_).trace(packet, depth, primary_shares(), walk);
    });
    if (tally != nullptr) {
        tally->add_pixel(walk.rays, walk.ledgers[0].dropped, walk.ledgers[0].over_budget);
    }
    return lane(color, 0);
}

Ray Tracer::primary_ray(int x, int y, int width, int height) const {
    RayPacket packet = with_precision_policy(precision_, [&](auto policy) {
        return CameraPacket(*scene_, width, height).template rays<decltype(policy)>(x, y, lane_0_only());
    });
    return {to_world(*scene_, lane(packet.origin, 0)), lane(packet.direction, 0)};
}

// Tiles of 16 × 16 pixels are handed to worker threads; within a tile, 2 × 2 pixels make a packet
// (coherent rays: they meet the same primitives). Each lane is computed alone, so the image is
// bit-identical for any thread count and equals the per-ray API's trace() of each pixel. A tile is
// rendered into a buffer of its own and copied into the image row by row when done: consecutive tiles
// run on different threads and share cache lines at their borders, which per-pixel writes would pass
// back and forth between the cores.
RenderResult render(const scene::Scene& scene, const RenderOptions& options) {
    return render(scene, options, {});
}

RenderResult render(const scene::Scene& scene, const RenderOptions& options, const Precision& precision) {
    return render(Tracer(scene, precision, options.accel), scene, options);
}

RenderResult render(const Tracer& tracer, const scene::Scene& scene, const RenderOptions& options) {
    const Precision& precision = tracer.precision();
    scene::ImageSize size = scene::resolve_image_size(scene, options.width, options.height);
    Image image(size.width, size.height);
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = process_cpu_seconds();
    TraceTally tally = with_precision_policy(precision, [&](auto policy) {
        using P = decltype(policy);
        PacketTracer<P> packets(tracer.compiled());
        CameraPacket camera(tracer.compiled(), size.width, size.height);
        return for_each_tile<TraceTally>(
            tracer.compiled(), size, options, precision.flush_denormals,
            [&](int x0, int y0, int x1, int y1, const PrimitiveLists& visible) {
                TraceTally tile_tally;
                Rgb pixels[tile][tile];
                for_each_packet(x0, y0, x1, y1, [&](int x, int y, vbool4 active) {
                    RayPacket packet = camera.template rays<P>(x, y, active);
                    PacketWalk walk;
                    Vec3x4 color = packets.trace(packet, visible, 1, primary_shares(), walk);
                    tile_tally.rays += walk.rays;
                    alignas(16) float r[4], g[4], b[4];
                    color.x.store(r);
                    color.y.store(g);
                    color.z.store(b);
                    // Buffer rows and columns past the image's edge are written but never copied.
                    for (int lane = 0; lane < 4; ++lane) {
                        pixels[y - y0 + (lane >> 1)][x - x0 + (lane & 1)] = {r[lane], g[lane], b[lane]};
                        const scene::PixelLedger& ledger = walk.ledgers[static_cast<std::size_t>(lane)];
                        TraceTally pixel;
                        pixel.add_pixel(0, ledger.dropped, ledger.over_budget);
                        tile_tally.add(pixel, static_cast<std::int64_t>(y + (lane >> 1)) * size.width + x + (lane & 1));
                    }
                });
                for (int y = y0; y < y1; ++y) {
                    std::copy(pixels[y - y0], pixels[y - y0] + (x1 - x0), &image.at(x0, y));
                }
                return tile_tally;
            });
    });
    return {std::move(image), tally, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
            process_cpu_seconds() - cpu_start};
}

FirstHits cast_primary_rays(const scene::Scene& scene, const RenderOptions& options, const Precision& precision) {
    scene::ImageSize size = scene::resolve_image_size(scene, options.width, options.height);
    Tracer tracer(scene, precision, options.accel);
    const double cpu_start = process_cpu_seconds();
    std::uint64_t hits = with_precision_policy(precision, [&](auto policy) {
        using P = decltype(policy);
        PacketTracer<P> packets(tracer.compiled());
        CameraPacket camera(tracer.compiled(), size.width, size.height);
        return for_each_tile<std::uint64_t>(tracer.compiled(), size, options, precision.flush_denormals,
                                            [&](int x0, int y0, int x1, int y1, const PrimitiveLists& visible) {
                                                std::uint64_t tile_hits = 0;
                                                for_each_packet(x0, y0, x1, y1, [&](int x, int y, vbool4 active) {
                                                    RayPacket packet = camera.template rays<P>(x, y, active);
                                                    tile_hits += lane_count(packets.intersect(packet, visible).hit);
                                                });
                                                return tile_hits;
                                            });
    });
    return {static_cast<std::uint64_t>(size.width) * static_cast<std::uint64_t>(size.height), hits,
            process_cpu_seconds() - cpu_start};
}

}  // namespace twinray::sse
