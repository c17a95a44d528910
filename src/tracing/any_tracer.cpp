#include "tracing/any_tracer.h"

#include "plugin/plugin.h"
#include "plugin/plugin_intersector.h"
#include "reference/tracer.h"
#include "sse/cpu.h"

#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <type_traits>

namespace twinray::tracing {
namespace {

constexpr std::string_view plugin_prefix = "plugin:";

template <typename V>
Vec3d widened(const V& v) {
    return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)};
}

template <typename H>
FirstHit first_hit(const std::optional<H>& hit) {
    if (!hit) {
        return {};
    }
    return {
        true,          hit->leaf, static_cast<double>(hit->t), widened(hit->point), widened(hit->normal), hit->triangle,
        hit->entering, hit->part};
}

// A tracer of twinray's own: `Ray` its ray type, built from double vectors (rounded where its members are float).
// `scene` is read again only by render().
template <typename Tracer, typename Ray>
class Native final : public AnyTracer {
public:
    template <typename... Build>
    Native(const scene::Scene& scene, std::string description, double unit_roundoff, Build&&... build)
        : scene_(scene),
          description_(std::move(description)),
          unit_roundoff_(unit_roundoff),
          tracer_(scene, std::forward<Build>(build)...) {}

    std::string description() const override { return description_; }
    double unit_roundoff() const override { return unit_roundoff_; }
    FirstHit intersect(const Vec3d& origin, const Vec3d& direction) const override {
        return first_hit(tracer_.intersect(ray(origin, direction)));
    }
    FirstHit primary_hit(int x, int y, int width, int height) const override {
        return first_hit(tracer_.intersect(tracer_.primary_ray(x, y, width, height)));
    }
    void trace_primary(int x, int y, int width, int height, RayTree& tree) const override {
        tracer_.trace(tracer_.primary_ray(x, y, width, height), 1, nullptr, &tree);
    }
    void trace_ray(const Vec3d& origin, const Vec3d& direction, RayTree& tree) const override {
        tracer_.trace(ray(origin, direction), 1, nullptr, &tree);
    }
    RenderResult render(const RenderOptions& options) const override {
        if constexpr (std::is_same_v<Tracer, sse::Tracer>) {
            return sse::render(tracer_, scene_, options);
        } else {
            return reference::render(tracer_, scene_, options);
        }
    }

private:
    static Ray ray(const Vec3d& origin, const Vec3d& direction) {
        return Ray{decltype(Ray::origin)(origin), decltype(Ray::direction)(direction)};
    }

    const scene::Scene& scene_;
    std::string description_;
    double unit_roundoff_;
    Tracer tracer_;
};

// A plug-in's hits, shaded, shadowed, reflected and refracted by reference<double> (plugin/plugin_intersector.h).
class PluginShaded final : public AnyTracer {
public:
    PluginShaded(const std::string& path, const scene::Scene& scene, Accel accel)
        : scene_(scene),
          plugin_(path),
          built_(plugin_, scene),
          intersector_(built_),
          tracer_(scene, accel, &intersector_) {}

    std::string description() const override {
        return "plugin " + plugin_.name() + " " + plugin_.version() + " (" + plugin_.path() +
               "), shaded by reference<double>";
    }
    double unit_roundoff() const override { return plugin_.unit_roundoff(); }
    FirstHit intersect(const Vec3d& origin, const Vec3d& direction) const override {
        return first_hit(tracer_.intersect({origin, direction}));
    }
    FirstHit primary_hit(int x, int y, int width, int height) const override {
        return first_hit(tracer_.intersect(tracer_.primary_ray(x, y, width, height)));
    }
    void trace_primary(int x, int y, int width, int height, RayTree& tree) const override {
        tracer_.trace(tracer_.primary_ray(x, y, width, height), 1, nullptr, &tree);
    }
    void trace_ray(const Vec3d& origin, const Vec3d& direction, RayTree& tree) const override {
        tracer_.trace({origin, direction}, 1, nullptr, &tree);
    }
    RenderResult render(const RenderOptions& options) const override {
        return reference::render(tracer_, scene_, options);
    }

private:
    const scene::Scene& scene_;
    plugin::Plugin plugin_;
    plugin::BuiltScene built_;
    plugin::PluginIntersector intersector_;
    reference::Tracer<double> tracer_;
};

constexpr double double_roundoff = std::numeric_limits<double>::epsilon() / 2;
constexpr double float_roundoff = std::numeric_limits<float>::epsilon() / 2;

struct Entry {
    std::string summary;
    std::unique_ptr<AnyTracer> (*make)(const scene::Scene&, const sse::Precision&, Accel);
};

const std::map<std::string, Entry>& registry() {
    static const std::map<std::string, Entry> tracers = {
        {"reference",
         {"scalar double-precision reference (the oracle)",
          [](const scene::Scene& scene, const sse::Precision&, Accel accel) -> std::unique_ptr<AnyTracer> {
              return std::make_unique<Native<reference::Tracer<double>, reference::Ray<double>>>(
                  scene, "reference<double>", double_roundoff, accel);
          }}},
        {"reference-float",
         {"the reference's code in single precision",
          [](const scene::Scene& scene, const sse::Precision&, Accel accel) -> std::unique_ptr<AnyTracer> {
              return std::make_unique<Native<reference::Tracer<float>, reference::Ray<float>>>(
                  scene, "reference<float>", float_roundoff, accel);
          }}},
        {"sse",
         {"single-precision SSE4.1 tracer, the fast one",
          [](const scene::Scene& scene, const sse::Precision& precision, Accel accel) -> std::unique_ptr<AnyTracer> {
              return std::make_unique<Native<sse::Tracer, sse::Ray>>(
                  scene, "sse (float, SSE4.1, " + sse::precision_name(precision) + ")", float_roundoff, precision,
                  accel);
          }}},
    };
    return tracers;
}

}  // namespace

const std::vector<std::string>& tracer_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> all;
        for (const auto& [name, entry] : registry()) {
            all.push_back(name);
        }
        return all;
    }();
    return names;
}

bool is_plugin(const std::string& name) {
    return name.starts_with(plugin_prefix);
}

std::string tracer_summary(const std::string& name) {
    return registry().at(name).summary;
}

std::string tracer_unavailable_reason(const std::string& name) {
    if (name == "sse" && !sse::cpu_supports_sse41()) {
        return sse::missing_sse41_message();
    }
    return "";
}

std::string precision_problem(const std::string& name, const sse::Precision& precision) {
    if (precision == sse::Precision{}) {
        return "";
    }
    if (name != "sse") {
        return "precision knobs (" + sse::precision_name(precision) + ") apply to --tracer sse only";
    }
    if (!sse::precision_is_built(precision)) {
        return "the SSE tracer is not built for the knobs " + sse::precision_name(precision) +
               "; built: " + sse::built_precisions();
    }
    return "";
}

std::unique_ptr<AnyTracer> make_tracer(const std::string& name, const scene::Scene& scene,
                                       const sse::Precision& precision, Accel accel) {
    if (std::string problem = precision_problem(name, precision); !problem.empty()) {
        throw std::invalid_argument(problem);
    }
    if (is_plugin(name)) {
        return std::make_unique<PluginShaded>(name.substr(plugin_prefix.size()), scene, accel);
    }
    auto entry = registry().find(name);
    if (entry == registry().end()) {
        throw std::invalid_argument("unknown tracer \"" + name + "\"");
    }
    return entry->second.make(scene, precision, accel);
}

}  // namespace twinray::tracing
