#include "cli/tracers.h"

#include "plugin/plugin_intersector.h"
#include "reference/tracer.h"
#include "sse/cpu.h"
#include "sse/tracer.h"

#include <functional>
#include <map>
#include <stdexcept>
#include <string_view>

namespace twinray::cli {
namespace {

struct TracerEntry {
    std::string description;
    std::function<RenderResult(const scene::Scene&, const RenderOptions&, const sse::Precision&)> render;
};

constexpr std::string_view plugin_prefix = "plugin:";

const std::map<std::string, TracerEntry>& registry() {
    static const std::map<std::string, TracerEntry> tracers = {
        {"reference",
         {"scalar double-precision reference (the oracle)",
          [](const scene::Scene& scene, const RenderOptions& options, const sse::Precision&) {
              return reference::render<double>(scene, options);
          }}},
        {"reference-float",
         {"the reference's code in single precision",
          [](const scene::Scene& scene, const RenderOptions& options, const sse::Precision&) {
              return reference::render<float>(scene, options);
          }}},
        {"sse",
         {"single-precision SSE4.1 tracer, the fast one",
          [](const scene::Scene& scene, const RenderOptions& options, const sse::Precision& precision) {
              return sse::render(scene, options, precision);
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

bool is_plugin(const std::string& tracer_name) {
    return tracer_name.starts_with(plugin_prefix);
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

RenderResult render_with(const std::string& tracer_name, const scene::Scene& scene, const RenderOptions& options,
                         const sse::Precision& precision) {
    if (std::string problem = precision_problem(tracer_name, precision); !problem.empty()) {
        throw std::invalid_argument(problem);
    }
    if (is_plugin(tracer_name)) {
        const plugin::Plugin loaded(tracer_name.substr(plugin_prefix.size()));
        const plugin::BuiltScene built(loaded, scene);
        const plugin::PluginIntersector intersector(built);
        return reference::render<double>(scene, options, &intersector);
    }
    auto entry = registry().find(tracer_name);
    if (entry == registry().end()) {
        throw std::invalid_argument("unknown tracer \"" + tracer_name + "\"");
    }
    return entry->second.render(scene, options, precision);
}

void add_tracer_option(CLI::App& command, std::string& tracer) {
    std::string help = "Tracer:";
    for (const std::string& name : tracer_names()) {
        help += " " + name + " (" + tracer_description(name) + ");";
    }
    help +=
        " or plugin:PATH (a tracer behind include/twinray/tracer.h, its hits shaded by the reference in double; "
        "docs/plugins.md)";
    command.add_option("--tracer", tracer, help)
        ->check(CLI::Validator(
            [](const std::string& name) -> std::string {
                if (registry().count(name) != 0 || (is_plugin(name) && name.size() > plugin_prefix.size())) {
                    return "";
                }
                std::string known;
                for (const std::string& each : tracer_names()) {
                    known += each + ", ";
                }
                return "unknown tracer \"" + name + "\"; known: " + known + "plugin:PATH";
            },
            "TRACER", "tracer"))
        ->capture_default_str();
}

void add_precision_options(CLI::App& command, sse::Precision& precision) {
    command.add_flag("--fast-rcp", precision.fast_rcp, "sse: divisions by _mm_rcp_ps + one Newton step");
    command.add_flag("--fast-rsqrt", precision.fast_rsqrt, "sse: normalisation by _mm_rsqrt_ps + one Newton step");
    command.add_flag("--dpps", precision.dpps, "sse: dot products transposed to AoS and _mm_dp_ps (the thesis's way)");
    command.add_flag("--textbook-quadratic", precision.textbook_quadratic,
                     "sse: textbook quadratic b^2 - ac instead of the cancellation-free form");
    command.add_flag("--moller-trumbore", precision.moller_trumbore,
                     "sse: triangles by Moller-Trumbore, not watertight, instead of the sheared watertight test");
    command.add_flag("--ftz", precision.flush_denormals, "sse: flush denormals to zero (MXCSR FTZ and DAZ)");
    command
        .add_option_function<std::string>(
            "--precision",
            [&precision](const std::string& preset) {
                bool fast = preset == "fast";
                precision.fast_rcp = precision.fast_rcp || fast;
                precision.fast_rsqrt = precision.fast_rsqrt || fast;
                precision.textbook_quadratic = precision.textbook_quadratic || fast;
                precision.flush_denormals = precision.flush_denormals || fast;
            },
            "sse: a preset: exact (the default) or fast (--fast-rcp --fast-rsqrt --textbook-quadratic --ftz)")
        ->check(CLI::IsMember({"exact", "fast"}));
}

std::string precision_problem(const std::string& tracer_name, const sse::Precision& precision) {
    if (precision == sse::Precision{}) {
        return "";
    }
    if (tracer_name != "sse") {
        return "precision knobs (" + sse::precision_name(precision) + ") apply to --tracer sse only";
    }
    if (!sse::precision_is_built(precision)) {
        return "the SSE tracer is not built for the knobs " + sse::precision_name(precision) +
               "; built: " + sse::built_precisions();
    }
    return "";
}

void add_accel_option(CLI::App& command, Accel& accel) {
    command
        .add_option_function<std::string>(
            "--accel",
            [&accel](const std::string& name) {
                accel = name == "none" ? Accel::none : name == "bvh" ? Accel::bvh : Accel::automatic;
            },
            "auto (the default: sse builds a BVH where testing every bounded object would cost more than " +
                std::to_string(sse::bvh_crossover) +
                " sphere tests, a box counting 2.7, a triangle 6.2, a CSG object its primitives and 2.2; the "
                "reference where they hold more than " +
                std::to_string(reference::bvh_crossover) +
                " primitives), none (every ray tests every object) or bvh; the image is the same")
        ->check(CLI::IsMember({"auto", "none", "bvh"}));
}

}  // namespace twinray::cli
