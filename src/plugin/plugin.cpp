#include "plugin/plugin.h"

#include <dlfcn.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <type_traits>
#include <utility>
#include <variant>

namespace twinray::plugin {
namespace {

constexpr std::size_t error_size = 1024;

struct KindName {
    std::uint32_t kind;
    const char* name;
};
constexpr std::array<KindName, 7> kind_names{{{TWINRAY_KIND_PLANE, "plane"},
                                              {TWINRAY_KIND_SPHERE, "sphere"},
                                              {TWINRAY_KIND_CYLINDER, "cylinder"},
                                              {TWINRAY_KIND_BOX, "box"},
                                              {TWINRAY_KIND_TRIANGLES, "triangles"},
                                              {TWINRAY_KIND_TRANSFORMED, "transformed primitive"},
                                              {TWINRAY_KIND_INSTANCES, "instances"}}};

void put(double (&to)[3], const scene::Vec3& from) {
    to[0] = from.x;
    to[1] = from.y;
    to[2] = from.z;
}

twinray_transform abi_transform(const math::Matrix3<double>& linear, const scene::Vec3& translation) {
    twinray_transform transform{};
    for (int row = 0; row < 3; ++row) {
        put(transform.linear[row], linear.row[row]);
    }
    put(transform.translation, translation);
    return transform;
}

// The scene as the ABI's arrays, with the kinds it holds; owned here for the length of the build.
struct FlatScene {
    std::vector<twinray_plane> planes;
    std::vector<twinray_sphere> spheres;
    std::vector<twinray_cylinder> cylinders;
    std::vector<twinray_box> boxes;
    std::vector<twinray_mesh> meshes, shapes;
    std::vector<twinray_instance> instances;
    std::vector<twinray_transform> transforms;
    std::vector<std::vector<double>> vertices;  // every mesh's and shape's, as the ABI lays them out
    std::uint32_t kinds = 0;
    bool csg = false;

    void add(const scene::Plane& plane, std::uint32_t object, std::uint32_t) {
        twinray_plane flat{};
        put(flat.normal, plane.normal);
        flat.offset = plane.offset;
        flat.object = object;
        planes.push_back(flat);
        kinds |= TWINRAY_KIND_PLANE;
    }
    void add(const scene::Sphere& sphere, std::uint32_t object, std::uint32_t transform) {
        twinray_sphere flat{};
        put(flat.center, sphere.center);
        flat.radius = sphere.radius;
        flat.object = object;
        flat.transform = transform;
        spheres.push_back(flat);
        kinds |= TWINRAY_KIND_SPHERE;
    }
    void add(const scene::Cylinder& cylinder, std::uint32_t object, std::uint32_t transform) {
        twinray_cylinder flat{};
        put(flat.base, cylinder.base);
        put(flat.cap, cylinder.cap);
        flat.radius = cylinder.radius;
        flat.object = object;
        flat.transform = transform;
        cylinders.push_back(flat);
        kinds |= TWINRAY_KIND_CYLINDER;
    }
    void add(const scene::Box& box, std::uint32_t object, std::uint32_t transform) {
        twinray_box flat{};
        put(flat.min, box.min);
        put(flat.max, box.max);
        flat.object = object;
        flat.transform = transform;
        boxes.push_back(flat);
        kinds |= TWINRAY_KIND_BOX;
    }
    template <typename S>
    void add(const scene::Transformed<S>& placed, std::uint32_t object, std::uint32_t) {
        transforms.push_back(abi_transform(placed.to_world().linear, placed.to_world().translation));
        add(placed.shape(), object, static_cast<std::uint32_t>(transforms.size() - 1));
        kinds |= TWINRAY_KIND_TRANSFORMED;
    }

    void add(const scene::Object& object) {
        std::visit(
            [&](const auto& shape) {
                using S = std::decay_t<decltype(shape)>;
                if constexpr (std::is_same_v<S, scene::Csg>) {
                    csg = true;
                    for (const scene::Object& child : shape.children) {
                        add(child);
                    }
                } else {
                    add(shape, static_cast<std::uint32_t>(object.leaf), TWINRAY_NONE);
                }
            },
            object.shape);
    }

    twinray_mesh mesh(const scene::MeshData& data, std::uint32_t object) {
        std::vector<double>& flat = vertices.emplace_back();
        flat.reserve(3 * data.vertices.size());
        for (const scene::Vec3& vertex : data.vertices) {
            flat.insert(flat.end(), {vertex.x, vertex.y, vertex.z});
        }
        static_assert(sizeof(std::array<std::uint32_t, 3>) == 3 * sizeof(std::uint32_t));
        return {flat.data(), static_cast<std::uint32_t>(data.vertices.size()),
                reinterpret_cast<const std::uint32_t*>(data.triangles.data()),
                static_cast<std::uint32_t>(data.triangles.size()), object};
    }

    explicit FlatScene(const scene::Scene& scene) {
        for (const scene::Object& object : scene.objects) {
            add(object);
        }
        csg = csg || !scene.solid_instances.empty();  // an instance of a CSG shape needs CSG as its tree does
        for (const scene::MeshShape& shape : scene.mesh_shapes) {
            shapes.push_back(mesh(*shape.data, TWINRAY_NONE));
        }
        for (const scene::Mesh& placed : scene.meshes) {
            const auto object = static_cast<std::uint32_t>(placed.leaf);
            if (placed.placement) {
                instances.push_back({static_cast<std::uint32_t>(placed.placement->shape), object,
                                     abi_transform(placed.placement->linear, placed.placement->translation)});
                kinds |= TWINRAY_KIND_INSTANCES | TWINRAY_KIND_TRIANGLES;
            } else {
                meshes.push_back(mesh(*placed.data, object));
                kinds |= TWINRAY_KIND_TRIANGLES;
            }
        }
    }

    twinray_scene view(std::uint32_t object_count, const scene::Vec3& eye) const {
        auto count = [](const auto& items) { return static_cast<std::uint32_t>(items.size()); };
        return {planes.data(),     count(planes), spheres.data(),       count(spheres),   cylinders.data(),
                count(cylinders),  boxes.data(),  count(boxes),         meshes.data(),    count(meshes),
                shapes.data(),     count(shapes), instances.data(),     count(instances), transforms.data(),
                count(transforms), object_count,  {eye.x, eye.y, eye.z}};
    }
};

std::vector<std::string> names_missing(std::uint32_t needed, bool csg, std::uint32_t kinds) {
    std::vector<std::string> missing;
    for (const KindName& kind : kind_names) {
        if ((needed & kind.kind) != 0 && (kinds & kind.kind) == 0) {
            missing.push_back(kind.name);
        }
    }
    if (csg) {
        missing.push_back("csg");
    }
    return missing;
}

std::string vector_text(const double (&v)[3]) {
    std::ostringstream text;
    text.precision(17);
    text << "(" << v[0] << ", " << v[1] << ", " << v[2] << ")";
    return text.str();
}

}  // namespace

UnsupportedKind::UnsupportedKind(const std::string& tracer, const std::string& kind)
    : PluginUnusable("the scene holds a " + kind + ", which the tracer \"" + tracer + "\" does not intersect"),
      kind_(kind) {}

Plugin::Plugin(const std::string& path) : path_(path) {
    void* library = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!library) {
        throw PluginUnusable("cannot load the plug-in " + path + ": " + dlerror());
    }
    auto entry = reinterpret_cast<twinray_tracer_entry_function>(dlsym(library, TWINRAY_TRACER_ENTRY_NAME));
    if (!entry) {
        throw PluginUnusable("the plug-in " + path + " exports no " + TWINRAY_TRACER_ENTRY_NAME +
                             " (include/twinray/tracer.h)");
    }
    table_ = entry();
    if (!table_) {
        throw PluginUnusable("the plug-in " + path + "'s " + TWINRAY_TRACER_ENTRY_NAME + " returned no table");
    }
    if (table_->abi_version != TWINRAY_TRACER_ABI_VERSION) {
        throw PluginUnusable("the plug-in " + path + " speaks the tracer ABI version " +
                             std::to_string(table_->abi_version) + "; this twinray speaks version " +
                             std::to_string(TWINRAY_TRACER_ABI_VERSION));
    }
    if (!table_->name || !table_->version || !table_->build || !table_->intersect || !table_->hits_along ||
        !table_->release) {
        throw PluginUnusable("the plug-in " + path + "'s table leaves a name, a version or a function empty");
    }
    if (!(table_->unit_roundoff > 0 && table_->unit_roundoff < 0.5)) {
        throw PluginUnusable("the plug-in " + path + " states a unit roundoff of " +
                             std::to_string(table_->unit_roundoff) + "; it must lie in (0, 0.5), 2^-24 for float");
    }
}

std::vector<std::string> missing_kinds(const scene::Scene& scene, std::uint32_t kinds) {
    FlatScene flat(scene);
    return names_missing(flat.kinds, flat.csg, kinds);
}

std::string Plugin::description() const {
    std::string kinds;
    for (const KindName& kind : kind_names) {
        if ((table_->kinds & kind.kind) != 0) {
            kinds += (kinds.empty() ? "" : ", ") + std::string(kind.name);
        }
    }
    char roundoff[32];
    std::snprintf(roundoff, sizeof roundoff, "%.3g", unit_roundoff());
    return name() + " " + version() + " (" + (kinds.empty() ? "none" : kinds) + "; unit roundoff " + roundoff + "; " +
           (thread_safe() ? "thread-safe" : "one thread") + ")";
}

std::vector<std::string> Plugin::missing_kinds(const scene::Scene& scene) const {
    return plugin::missing_kinds(scene, table_->kinds);
}

std::unique_ptr<JudgedScene> Plugin::build(const scene::Scene& scene) const {
    return std::make_unique<BuiltScene>(*this, scene);
}

BuiltScene::BuiltScene(const Plugin& plugin, const scene::Scene& scene) : plugin_(plugin) {
    FlatScene flat(scene);
    if (std::vector<std::string> missing = names_missing(flat.kinds, flat.csg, plugin.table().kinds);
        !missing.empty()) {
        throw UnsupportedKind(plugin.name(), missing.front());
    }
    triangles_of_leaf_.assign(scene.leaf_paths.size(), -1);
    instance_of_leaf_.assign(scene.leaf_paths.size(), -1);
    int instance = 0;
    for (const scene::Mesh& mesh : scene.meshes) {
        triangles_of_leaf_[static_cast<std::size_t>(mesh.leaf)] =
            static_cast<std::int64_t>(mesh.data->triangles.size());
        if (mesh.placement) {
            instance_of_leaf_[static_cast<std::size_t>(mesh.leaf)] = instance++;
        }
    }
    const twinray_scene view = flat.view(static_cast<std::uint32_t>(scene.leaf_paths.size()), scene.camera.eye);
    char error[error_size] = "";
    built_ = plugin.table().build(&view, error, sizeof error);
    if (!built_) {
        throw PluginUnusable("the tracer \"" + plugin.name() + "\" could not build the scene: " + error);
    }
}

BuiltScene::~BuiltScene() {
    plugin_.table().release(built_);
}

void BuiltScene::fault(const twinray_ray& ray, const std::string& what) const {
    std::ostringstream text;
    text.precision(17);
    text << "the tracer \"" << plugin_.name() << "\" " << what << " for the ray from " << vector_text(ray.origin)
         << " along " << vector_text(ray.direction) << ", t in (" << ray.t_min << ", " << ray.t_max << ")";
    throw PluginFault(text.str());
}

Hit BuiltScene::checked(const twinray_ray& ray, const twinray_hit& hit) const {
    if (hit.hit == 0) {
        return {};
    }
    std::ostringstream what;
    what.precision(17);
    if (hit.hit != 1) {
        what << "returned hit = " << hit.hit << " (0 or 1)";
    } else if (!(hit.t > ray.t_min && hit.t < ray.t_max)) {
        what << "returned t = " << hit.t << ", outside the ray's range";
    } else if (hit.object >= triangles_of_leaf_.size()) {
        what << "returned object " << hit.object << " of " << triangles_of_leaf_.size();
    } else {
        const std::int64_t triangles = triangles_of_leaf_[hit.object];
        const int instance = instance_of_leaf_[hit.object];
        const double length =
            std::sqrt(hit.normal[0] * hit.normal[0] + hit.normal[1] * hit.normal[1] + hit.normal[2] * hit.normal[2]);
        if (triangles < 0 ? hit.primitive != TWINRAY_NONE : hit.primitive >= triangles) {
            what << "returned primitive " << hit.primitive << " on object " << hit.object << " ("
                 << (triangles < 0 ? "not a mesh: TWINRAY_NONE" : std::to_string(triangles) + " triangles") << ")";
        } else if (instance < 0 ? hit.instance != TWINRAY_NONE : hit.instance != static_cast<std::uint32_t>(instance)) {
            what << "returned instance " << hit.instance << " on object " << hit.object
                 << " (its instance: " << (instance < 0 ? std::string("none, TWINRAY_NONE") : std::to_string(instance))
                 << ")";
        } else if (!(std::abs(length - 1) < 1e-3)) {
            what << "returned a normal " << vector_text(hit.normal) << " of length " << length << " (unit)";
        } else if (!std::isfinite(hit.u) || !std::isfinite(hit.v)) {
            what << "returned barycentrics u = " << hit.u << ", v = " << hit.v;
        } else if (hit.entering > 1) {
            what << "returned entering = " << hit.entering << " (0 or 1)";
        } else {
            return {true,
                    static_cast<int>(hit.object),
                    triangles < 0 ? -1 : static_cast<int>(hit.primitive),
                    instance,
                    hit.t,
                    {hit.normal[0], hit.normal[1], hit.normal[2]},
                    hit.u,
                    hit.v,
                    hit.entering == 1};
        }
    }
    fault(ray, what.str());
}

void BuiltScene::intersect(std::span<const twinray_ray> rays, std::span<Hit> hits) const {
    if (rays.empty()) {
        return;
    }
    std::vector<twinray_hit> answers(rays.size());
    std::size_t written = 0;
    char error[error_size] = "";
    int status = 0;
    {
        std::unique_lock<std::mutex> lock(calls_, std::defer_lock);
        if (!plugin_.thread_safe()) {
            lock.lock();
        }
        status =
            plugin_.table().intersect(built_, rays.data(), rays.size(), answers.data(), &written, error, sizeof error);
    }
    if (status != 0) {
        fault(rays.front(), "failed (status " + std::to_string(status) + ": " + error + ") in a batch of " +
                                std::to_string(rays.size()) + " rays beginning");
    }
    if (written != rays.size()) {
        fault(rays.front(), "wrote " + std::to_string(written) + " hits for a batch of " + std::to_string(rays.size()) +
                                " rays beginning");
    }
    for (std::size_t i = 0; i < rays.size(); ++i) {
        hits[i] = checked(rays[i], answers[i]);
    }
}

namespace {}  // namespace

Hit BuiltScene::nearest(const scene::Vec3& origin, const scene::Vec3& direction, double t_min, double t_max) const {
    const twinray_ray ray = abi_ray(origin, direction, t_min, t_max);
    Hit hit;
    intersect({&ray, 1}, {&hit, 1});
    return hit;
}

std::vector<Hit> BuiltScene::hits_along(const scene::Vec3& origin, const scene::Vec3& direction, double t_min,
                                        double t_max) const {
    const twinray_ray ray = abi_ray(origin, direction, t_min, t_max);
    std::vector<twinray_hit> answers(8);
    for (;;) {
        std::size_t total = 0;
        char error[error_size] = "";
        int status = 0;
        {
            std::unique_lock<std::mutex> lock(calls_, std::defer_lock);
            if (!plugin_.thread_safe()) {
                lock.lock();
            }
            status =
                plugin_.table().hits_along(built_, &ray, answers.data(), answers.size(), &total, error, sizeof error);
        }
        if (status != 0) {
            fault(ray, "failed (status " + std::to_string(status) + ": " + error + ") listing the hits");
        }
        if (total <= answers.size()) {
            answers.resize(total);
            break;
        }
        if (total > std::size_t{1} << 24) {
            fault(ray, "counted " + std::to_string(total) + " hits along one segment");
        }
        answers.resize(total);
    }
    std::vector<Hit> hits;
    hits.reserve(answers.size());
    for (const twinray_hit& answer : answers) {
        if (answer.hit != 1) {
            fault(ray, "listed a miss (hit = " + std::to_string(answer.hit) + ") among the hits along a segment");
        }
        hits.push_back(checked(ray, answer));
        if (hits.size() > 1 && hits[hits.size() - 2].t > hits.back().t) {
            fault(ray, "listed the hits along a segment out of order (t = " + std::to_string(hits[hits.size() - 2].t) +
                           " before " + std::to_string(hits.back().t) + ")");
        }
    }
    return hits;
}

}  // namespace twinray::plugin
