// A tracer of anyone's behind the C ABI of include/twinray/tracer.h: loaded from its shared library, given a scene
// as the ABI's flat arrays, asked for hits, and every answer checked against the ABI's contract before twinray
// uses it, so that a wrong answer is reported with the ray that shows it (docs/plugins.md).
#pragma once

#include "plugin/judged_tracer.h"
#include "scene/scene.h"
#include "twinray/tracer.h"

#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace twinray::plugin {

// Anything a plug-in does wrong: one of the two below.
class PluginError : public std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The plug-in cannot be used: its library does not load, lacks the entry point, speaks another ABI version,
// its build failed, or the scene holds a kind it lacks.
class PluginUnusable : public PluginError {
    using PluginError::PluginError;
};

// The scene holds a kind of primitive the plug-in does not intersect (`kind`: "plane", "csg", ...).
class UnsupportedKind : public PluginUnusable {
public:
    UnsupportedKind(const std::string& tracer, const std::string& kind);
    const std::string& kind() const { return kind_; }

private:
    std::string kind_;
};

// An answer that breaks the ABI's contract (a NaN, a t outside the ray's range, an object that is not the
// scene's, the wrong number of hits, a failed call), with the ray that shows it.
class PluginFault : public PluginError {
    using PluginError::PluginError;
};

class Plugin final : public JudgedTracer {
public:
    // Loads the library at `path` (dlopen, as a path: "./x.so" is not looked for on the library path) and
    // checks its table. The library stays loaded for the life of the process.
    explicit Plugin(const std::string& path);

    const std::string& path() const { return path_; }
    const twinray_tracer& table() const { return *table_; }
    std::string name() const { return table_->name; }
    std::string version() const { return table_->version; }
    double unit_roundoff() const override { return table_->unit_roundoff; }
    bool thread_safe() const { return (table_->flags & TWINRAY_TRACER_THREAD_SAFE) != 0; }
    std::string description() const override;
    std::vector<std::string> missing_kinds(const scene::Scene& scene) const override;
    // Throws UnsupportedKind and PluginUnusable as BuiltScene does.
    std::unique_ptr<JudgedScene> build(const scene::Scene& scene) const override;

private:
    std::string path_;
    const twinray_tracer* table_ = nullptr;
};

// The names of the kinds `scene` holds that a tracer with `kinds` (TWINRAY_KIND_*) lacks, in the ABI's order;
// "csg" for any CSG (version 1 carries none).
std::vector<std::string> missing_kinds(const scene::Scene& scene, std::uint32_t kinds);

// The plug-in's structure for one scene, built on construction and released on destruction.
class BuiltScene final : public JudgedScene {
public:
    // Throws UnsupportedKind where the scene holds a kind the plug-in lacks, PluginUnusable where its build
    // fails.
    BuiltScene(const Plugin& plugin, const scene::Scene& scene);
    ~BuiltScene() override;
    BuiltScene(const BuiltScene&) = delete;
    BuiltScene& operator=(const BuiltScene&) = delete;

    const Plugin& plugin() const { return plugin_; }

    // The nearest hit of each ray (hits.size() == rays.size()), each checked; throws PluginFault.
    void intersect(std::span<const twinray_ray> rays, std::span<Hit> hits) const override;
    Hit nearest(const scene::Vec3& origin, const scene::Vec3& direction, double t_min, double t_max) const;
    // Every hit with t_min < t < t_max, by increasing t, each checked; throws PluginFault.
    std::vector<Hit> hits_along(const scene::Vec3& origin, const scene::Vec3& direction, double t_min,
                                double t_max) const override;

private:
    Hit checked(const twinray_ray& ray, const twinray_hit& hit) const;
    [[noreturn]] void fault(const twinray_ray& ray, const std::string& what) const;

    const Plugin& plugin_;
    void* built_ = nullptr;
    // By leaf: the triangles of its mesh or shape, -1 for any other primitive; and the instance it is, or -1.
    std::vector<std::int64_t> triangles_of_leaf_;
    std::vector<int> instance_of_leaf_;
    mutable std::mutex calls_;  // held around every call into a plug-in that is not thread-safe
};

}  // namespace twinray::plugin
