#include "sse/tracer.h"

#include "sse/compiled_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace twinray::sse {
namespace {

// Tag bits of a nearest hit: the crossing's tag (face, flipped) plus whether the ray enters there.
constexpr std::int32_t tag_entering = 0x20;

// The nearest crossing so far, per lane; reduced across lanes once per ray.
struct Nearest4 {
    vfloat4 t{infinity};
    vint4 leaf{-1};
    vint4 tag{0};
};

// A primitive's first crossing after t = 0 is its enter if that lies ahead, else its exit. Only a
// strictly nearer crossing replaces the lane's best, so at equal t the earlier primitive stays.
inline void keep_nearest(Nearest4& nearest, const Span4& span, vint4 leaf) {
    vfloat4 zero(0.0f);
    vbool4 entering = span.enter > zero;
    vfloat4 t = select(entering, span.enter, span.exit);
    vint4 tag = select(entering, span.enter_face | vint4(tag_entering), span.exit_face);
    vbool4 nearer = span.valid & (t > zero) & (t < nearest.t);
    nearest.t = select(nearer, t, nearest.t);
    nearest.leaf = select(nearer, leaf, nearest.leaf);
    nearest.tag = select(nearer, tag, nearest.tag);
}

struct ScalarNearest {
    float t = infinity;
    std::int32_t leaf = -1;
    std::int32_t tag = 0;

    // Smaller t wins; at equal t the smaller leaf, i.e. the object earlier in the file.
    void offer(float candidate_t, std::int32_t candidate_leaf, std::int32_t candidate_tag) {
        if (candidate_leaf >= 0 && (candidate_t < t || (candidate_t == t && candidate_leaf < leaf))) {
            t = candidate_t;
            leaf = candidate_leaf;
            tag = candidate_tag;
        }
    }
};

template <typename Block, typename Visit>
void for_each_block(const BlockList<Block>& list, Visit&& visit) {
    for (std::size_t i = 0; i < list.blocks.size(); ++i) {
        visit(list.blocks[i], list.ids[i], list.transmission[i]);
    }
}

// Calls visit(span, ids, transmission) for every block of every primitive type present.
template <typename Lists, typename Visit>
void for_each_span(const Lists& lists, const Ray4& ray, Visit&& visit) {
    auto visit_block = [&](const auto& block, const IntLanes& ids, const FloatLanes& transmission) {
        visit(spans(block, ray), ids, transmission);
    };
    for_each_block(lists.planes, visit_block);
    for_each_block(lists.spheres, visit_block);
    for_each_block(lists.cylinders, visit_block);
    for_each_block(lists.boxes, visit_block);
}

// A CSG object's spans along the ray: every leaf's span computed four at a time, then the tree folded
// bottom-up in stack arrays.
class CsgEvaluation {
public:
    CsgEvaluation(const CsgObject& object, const Ray4& ray) : object_(object) {
        for_each_span(object, ray, [&](const Span4& span, const IntLanes& slots, const FloatLanes&) {
            alignas(16) float enter[4], exit[4];
            alignas(16) std::int32_t enter_face[4], exit_face[4];
            span.enter.store(enter);
            span.exit.store(exit);
            span.enter_face.store(enter_face);
            span.exit_face.store(exit_face);
            int valid = movemask(span.valid);
            for (int lane = 0; lane < 4; ++lane) {
                int slot = slots.value[lane];
                if (slot < 0) {
                    continue;
                }
                LeafSpan& leaf = leaf_spans_[slot];
                leaf.valid = (valid >> lane) & 1;
                std::int32_t id = object.slot_leaf[static_cast<std::size_t>(slot)];
                leaf.enter = {enter[lane], std::isinf(enter[lane]) ? -1 : id, enter_face[lane]};
                leaf.exit = {exit[lane], std::isinf(exit[lane]) ? -1 : id, exit_face[lane]};
            }
        });
    }

    void evaluate(SpanArray& out) const { evaluate(0, out); }

private:
    struct LeafSpan {
        bool valid;
        Crossing enter, exit;
    };

    void evaluate(int node_index, SpanArray& out) const {
        const CsgNodeF& node = object_.nodes[static_cast<std::size_t>(node_index)];
        if (node.slot >= 0) {
            out.clear();
            const LeafSpan& leaf = leaf_spans_[node.slot];
            if (leaf.valid) {
                out.push(leaf.enter, leaf.exit);
            }
            return;
        }
        const int* children = &object_.children_of[static_cast<std::size_t>(node.first_child)];
        SpanArray operand, scratch, other;
        SpanArray* accumulated = &out;
        SpanArray* combined = &other;
        evaluate(children[0], *accumulated);
        for (int i = 1; i < node.child_count; ++i) {
            evaluate(children[i], operand);
            csg_combine(node.op, *accumulated, operand, scratch, *combined);
            std::swap(accumulated, combined);
        }
        if (accumulated != &out) {
            out.assign(*accumulated);
        }
    }

    const CsgObject& object_;
    LeafSpan leaf_spans_[scene::max_csg_leaves];
};

Vec3 outward_normal(const LeafInfo& leaf, std::int32_t tag, Vec3 point) {
    Vec3 normal;
    std::int32_t face = tag & tag_face_mask;
    switch (leaf.kind) {
        case LeafKind::plane: normal = leaf.direction; break;
        case LeafKind::sphere: normal = normalize(point - leaf.position); break;
        case LeafKind::box: {
            float sign = (face & 1) ? 1.0f : -1.0f;
            int axis = face >> 1;
            normal = {axis == 0 ? sign : 0.0f, axis == 1 ? sign : 0.0f, axis == 2 ? sign : 0.0f};
            break;
        }
        case LeafKind::cylinder:
            if (face == cylinder_side) {
                Vec3 w = point - leaf.position;
                normal = normalize(w - dot(w, leaf.direction) * leaf.direction);
            } else {
                normal = face == cylinder_top_cap ? leaf.direction : -leaf.direction;
            }
            break;
    }
    return (tag & tag_flipped) ? -normal : normal;
}

Vec3 reflect(Vec3 d, Vec3 n) { return d - (2.0f * dot(d, n)) * n; }

// Snell's law, as in the reference; false on total internal reflection.
bool refract(Vec3 d, Vec3 n, float eta, Vec3& refracted) {
    float cos_incident = -dot(d, n);
    float sin2_transmitted = eta * eta * (1.0f - cos_incident * cos_incident);
    if (sin2_transmitted > 1.0f) {
        return false;
    }
    float cos_transmitted = std::sqrt(1.0f - sin2_transmitted);
    refracted = normalize(eta * d + (eta * cos_incident - cos_transmitted) * n);
    return true;
}

// The reference's rule (docs/reference-tracer.md): start off the surface on the side the ray leaves to,
// by 64·ε·(|p|∞ + t), which bounds the hit point's rounding error with an order of magnitude to spare.
Vec3 spawn_origin(const Hit& hit, Vec3 direction) {
    float offset = 64.0f * std::numeric_limits<float>::epsilon() * (max_abs_component(hit.point) + hit.t);
    float side = dot(direction, hit.normal) >= 0.0f ? 1.0f : -1.0f;
    return hit.point + (side * offset) * hit.normal;
}

class Shader {
public:
    explicit Shader(const CompiledScene& scene) : scene_(scene) {}

    std::optional<Hit> intersect(const Ray& ray) const {
        Ray4 ray4(ray, scene_.any_box_test);
        Nearest4 nearest;
        for_each_span(scene_, ray4, [&](const Span4& span, const IntLanes& ids, const FloatLanes&) {
            keep_nearest(nearest, span, vint4::load(ids.value));
        });
        ScalarNearest best;
        alignas(16) float t[4];
        alignas(16) std::int32_t leaf[4], tag[4];
        nearest.t.store(t);
        nearest.leaf.store(leaf);
        nearest.tag.store(tag);
        for (int lane = 0; lane < 4; ++lane) {
            best.offer(t[lane], leaf[lane], tag[lane]);
        }
        for_each_csg_object_met(ray4, [&] { return best.t; }, [&](const CsgObject& object) {
            nearest_csg_crossing(object, ray4, best);
        });
        if (best.leaf < 0) {
            return std::nullopt;
        }
        Hit hit;
        hit.t = best.t;
        hit.point = ray.origin + best.t * ray.direction;
        Vec3 outward = outward_normal(scene_.leaves[static_cast<std::size_t>(best.leaf)], best.tag, hit.point);
        hit.normal = dot(outward, ray.direction) > 0.0f ? -outward : outward;
        hit.leaf = best.leaf;
        hit.entering = (best.tag & tag_entering) != 0;
        return hit;
    }

    Color trace(const Ray& ray, int depth, std::uint64_t& rays) const {
        ++rays;
        std::optional<Hit> hit = intersect(ray);
        return hit ? shade(ray, *hit, depth, rays) : scene_.background;
    }

private:
    // Calls visit(object) for each CSG object whose bound the ray meets between 0 and limit() (read
    // again before each object, as the nearest hit so far shrinks it).
    template <typename Limit, typename Visit>
    void for_each_csg_object_met(const Ray4& ray, Limit&& limit, Visit&& visit) const {
        for_each_block(scene_.csg_bounds, [&](const BoxBlock& block, const IntLanes& ids, const FloatLanes&) {
            Span4 span = spans(block, ray);
            alignas(16) float enter[4], exit[4];
            span.enter.store(enter);
            span.exit.store(exit);
            int met = movemask(span.valid);
            for (int lane = 0; lane < 4; ++lane) {
                if (((met >> lane) & 1) && exit[lane] > 0.0f && enter[lane] < limit()) {
                    visit(scene_.csg_objects[static_cast<std::size_t>(ids.value[lane])]);
                }
            }
        });
    }

    static void nearest_csg_crossing(const CsgObject& object, const Ray4& ray, ScalarNearest& best) {
        SpanArray spans;
        CsgEvaluation(object, ray).evaluate(spans);
        for (int i = 0; i < spans.count; ++i) {
            bool entering = spans.enter[i].t > 0.0f;
            const Crossing& crossing = entering ? spans.enter[i] : spans.exit[i];
            if (crossing.t > 0.0f) {
                best.offer(crossing.t, crossing.leaf, crossing.tag | (entering ? tag_entering : 0));
                return;
            }
        }
    }

    // The product of the transmission of every surface crossed strictly between origin and light.
    float shadow_transmittance(Vec3 origin, Vec3 light_position) const {
        Vec3 to_light = light_position - origin;
        float distance = length(to_light);
        Ray4 ray(Ray{origin, (1.0f / distance) * to_light}, scene_.any_box_test);
        vfloat4 zero(0.0f), one(1.0f), limit(distance);
        vfloat4 transmittance = one;
        bool blocked = false;
        for_each_span(scene_, ray, [&](const Span4& span, const IntLanes&, const FloatLanes& transmission) {
            if (blocked) {
                return;
            }
            vbool4 enter_between = span.valid & (span.enter > zero) & (span.enter < limit);
            vbool4 exit_between = span.valid & (span.exit > zero) & (span.exit < limit);
            if (!scene_.any_transparency) {
                blocked = any(enter_between | exit_between);
                return;
            }
            vfloat4 surface = vfloat4::load(transmission.value);
            transmittance = transmittance * select(enter_between, surface, one) * select(exit_between, surface, one);
        });
        if (blocked) {
            return 0.0f;
        }
        float product = transmittance.lane(0) * transmittance.lane(1) * transmittance.lane(2) * transmittance.lane(3);
        for_each_csg_object_met(ray, [&] { return distance; }, [&](const CsgObject& object) {
            if (product == 0.0f) {
                return;
            }
            SpanArray spans;
            CsgEvaluation(object, ray).evaluate(spans);
            for (int i = 0; i < spans.count; ++i) {
                for (const Crossing* crossing : {&spans.enter[i], &spans.exit[i]}) {
                    if (crossing->leaf >= 0 && crossing->t > 0.0f && crossing->t < distance) {
                        product *= material_of(crossing->leaf).transmission;
                    }
                }
            }
        });
        return product;
    }

    const MaterialF& material_of(std::int32_t leaf) const {
        return scene_.materials[static_cast<std::size_t>(scene_.leaves[static_cast<std::size_t>(leaf)].material)];
    }

    Color shade(const Ray& ray, const Hit& hit, int depth, std::uint64_t& rays) const {
        const MaterialF& m = material_of(hit.leaf);
        Color color = m.ambient * (m.color * scene_.ambient_light);
        Vec3 mirror = reflect(ray.direction, hit.normal);
        for (const LightF& light : scene_.lights) {
            Vec3 to_light = normalize(light.position - hit.point);
            float lambert = dot(hit.normal, to_light);
            if (!(lambert > 0.0f)) {
                continue;
            }
            ++rays;
            float shadow = shadow_transmittance(spawn_origin(hit, to_light), light.position);
            if (shadow == 0.0f) {
                continue;
            }
            Color diffuse = (m.diffuse * lambert) * (m.color * light.color);
            float highlight = m.phong > 0.0f ? m.phong * std::pow(std::fmax(0.0f, dot(mirror, to_light)), m.phong_size) : 0.0f;
            color += shadow * (diffuse + highlight * light.color);
        }
        if (depth >= scene_.max_depth) {
            return color;
        }
        float reflection = m.reflection;
        if (m.transmission > 0.0f) {
            float eta = hit.entering ? 1.0f / m.ior : m.ior;
            Vec3 refracted;
            if (refract(ray.direction, hit.normal, eta, refracted)) {
                color += m.transmission * trace({spawn_origin(hit, refracted), refracted}, depth + 1, rays);
            } else {
                reflection += m.transmission;
            }
        }
        if (reflection > 0.0f) {
            color += reflection * trace({spawn_origin(hit, mirror), mirror}, depth + 1, rays);
        }
        return color;
    }

    const CompiledScene& scene_;
};

}  // namespace

Tracer::Tracer(const scene::Scene& scene) : scene_(std::make_unique<CompiledScene>(compile(scene))) {}

Tracer::~Tracer() = default;

std::optional<Hit> Tracer::intersect(const Ray& ray) const {
    return Shader(*scene_).intersect(ray);
}

Color Tracer::trace(const Ray& ray, int depth, std::uint64_t* rays) const {
    std::uint64_t count = 0;
    Color color = Shader(*scene_).trace(ray, depth, count);
    if (rays != nullptr) {
        *rays += count;
    }
    return color;
}

// The reference's camera (reference/tracer.cpp), in float.
Ray Tracer::primary_ray(int x, int y, int width, int height) const {
    const CompiledScene& s = *scene_;
    float half_height = s.half_width * static_cast<float>(height) / static_cast<float>(width);
    float u = (2.0f * (static_cast<float>(x) + 0.5f) / static_cast<float>(width) - 1.0f) * s.half_width;
    float v = (1.0f - 2.0f * (static_cast<float>(y) + 0.5f) / static_cast<float>(height)) * half_height;
    return {s.eye, normalize(s.forward + u * s.right + v * s.up)};
}

// Tiles of 16 × 16 pixels keep a worker's rays coherent in cache; each pixel is computed alone, so the
// image is bit-identical for any thread count.
RenderResult render(const scene::Scene& scene, const RenderOptions& options) {
    constexpr int tile = 16;
    scene::ImageSize size = scene::resolve_image_size(scene, options.width, options.height);
    Tracer tracer(scene);
    Image image(size.width, size.height);
    int tiles_x = (size.width + tile - 1) / tile;
    int tiles_y = (size.height + tile - 1) / tile;
    std::uint64_t rays = parallel_for(
        tiles_x * tiles_y, options.threads,
        [&](int index) {
            std::uint64_t tile_rays = 0;
            int x0 = (index % tiles_x) * tile;
            int y0 = (index / tiles_x) * tile;
            for (int y = y0; y < std::min(y0 + tile, size.height); ++y) {
                for (int x = x0; x < std::min(x0 + tile, size.width); ++x) {
                    Color c = tracer.trace(tracer.primary_ray(x, y, size.width, size.height), 1, &tile_rays);
                    image.at(x, y) = {c.x, c.y, c.z};
                }
            }
            return tile_rays;
        },
        options.progress);
    return {std::move(image), rays};
}

}  // namespace twinray::sse
