#include "cli/tracers.h"

#include "reference/tracer.h"
#include "sse/cpu.h"
#include "sse/tracer.h"

#include <functional>
#include <map>
#include <stdexcept>

namespace twinray::cli {
namespace {

struct TracerEntry {
    std::string description;
    std::function<RenderResult(const scene::Scene&, const RenderOptions&)> render;
};

const std::map<std::string, TracerEntry>& registry() {
    static const std::map<std::string, TracerEntry> tracers = {
        {"reference", {"scalar double-precision reference (the oracle)", reference::render<double>}},
        {"reference-float", {"the reference's code in single precision", reference::render<float>}},
        {"sse", {"single-precision SSE4.1 tracer, the fast one", sse::render}},
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

std::string tracer_description(const std::string& name) {
    return registry().at(name).description;
}

std::string tracer_unavailable_reason(const std::string& name) {
    if (name == "sse" && !sse::cpu_supports_sse41()) {
        return sse::missing_sse41_message();
    }
    return "";
}

RenderResult render_with(const std::string& tracer_name, const scene::Scene& scene, const RenderOptions& options) {
    auto entry = registry().find(tracer_name);
    if (entry == registry().end()) {
        throw std::invalid_argument("unknown tracer \"" + tracer_name + "\"");
    }
    return entry->second.render(scene, options);
}

}  // namespace twinray::cli
