#include "peers/embree_peer.h"

#include "io/shared_module.h"
#include "peers/embree_module.h"

#include <stdexcept>

namespace twinray::peers {
namespace {

// The module installed beside twinray, else in this build tree (both paths set by src/cli/CMakeLists.txt).
const EmbreeFunctions& load_module() {
    return io::load_shared_module<EmbreeFunctions>(
        io::installed_or_built(TWINRAY_EMBREE_MODULE_INSTALLED, TWINRAY_EMBREE_MODULE).c_str(),
        "twinray_embree_functions", "the Embree module");
}

const EmbreeFunctions& module_functions() {
    static const EmbreeFunctions& functions = load_module();
    return functions;
}

}  // namespace

std::string embree_unsupported_reason(const scene::Scene& scene) {
    return scene.has_csg() ? "CSG" : "";
}

struct EmbreePeer::State {
    State(const EmbreeFunctions& functions, void* scene) : module(functions), embree(scene) {}
    State(const State&) = delete;
    State& operator=(const State&) = delete;
    ~State() { module.destroy(embree); }

    const EmbreeFunctions& module;
    void* embree;
};

EmbreePeer::EmbreePeer(const scene::Scene& scene, int width, EmbreeIsa isa, EmbreeMode mode) {
    const scene::ImageSize size = scene::resolve_image_size(scene, width, 0);
    const sse::Tracer camera(scene, {}, Accel::none);  // for its camera only: no BVH to build
    std::vector<sse::Ray> rays;
    rays.reserve(static_cast<std::size_t>(size.width) * static_cast<std::size_t>(size.height));
    for (int y = 0; y < size.height; ++y) {
        for (int x = 0; x < size.width; ++x) {
            rays.push_back(camera.primary_ray(x, y, size.width, size.height));
        }
    }
    const EmbreeFunctions& module = module_functions();
    state_ = std::make_unique<State>(module, module.create(scene, std::move(rays), size.width, size.height, isa, mode));
}

EmbreePeer::~EmbreePeer() = default;

FirstHitRun EmbreePeer::cast_single() const {
    return state_->module.cast_single(state_->embree);
}

FirstHitRun EmbreePeer::cast_packets(int lanes) const {
    return state_->module.cast_packets(state_->embree, lanes);
}

double EmbreePeer::build_seconds() const {
    return state_->module.build_seconds(state_->embree);
}

}  // namespace twinray::peers
