#include "cli/tracers.h"

#include "cli/exit_codes.h"

#include "reference/tracer.h"
#include "sse/tracer.h"

#include <algorithm>
#include <cstdio>
#include <string_view>

namespace twinray::cli {

RenderResult render_with(const std::string& tracer_name, const scene::Scene& scene, const RenderOptions& options,
                         const sse::Precision& precision) {
    return tracing::make_tracer(tracer_name, scene, precision, options.accel)->render(options);
}

RenderResult render_giving_up_geometry(const std::string& tracer_name, scene::Scene& scene,
                                       const RenderOptions& options, const sse::Precision& precision,
                                       std::string* accel_choice) {
    if (tracer_name != "sse") {
        return render_with(tracer_name, scene, options, precision);
    }
    if (std::string problem = precision_problem(tracer_name, precision); !problem.empty()) {
        throw std::invalid_argument(problem);
    }
    const sse::Tracer tracer(scene, sse::Tracer::give_up_geometry, precision, options.accel);
    if (accel_choice != nullptr && options.accel == Accel::automatic) {
        const sse::BvhStats stats = tracer.bvh_stats();
        char text[160];
        std::snprintf(text, sizeof text, "%s: the bounded objects weigh %.1f sphere tests, %s %zu%s",
                      stats.items > 0 ? "bvh" : "brute force", stats.brute_force_weight,
                      stats.items > 0 ? "above" : "not above", stats.crossover,
                      stats.crossover == sse::bvh_crossover ? "" : " (a material reflects or transmits)");
        *accel_choice = text;
    }
    return sse::render(tracer, scene, options);
}

int plugin_exit_status(const plugin::PluginError& error) {
    if (dynamic_cast<const plugin::UnsupportedKind*>(&error) != nullptr) {
        return exit_plugin_lacks_kind;
    }
    return dynamic_cast<const plugin::PluginFault*>(&error) != nullptr ? exit_plugin_fault : exit_plugin_unusable;
}

void add_plugin_option(CLI::App& command, std::vector<std::string>& plugins) {
    command
        .add_option("--tracer", plugins,
                    "plugin:PATH, repeatable: a tracer behind include/twinray/tracer.h, its hits shaded by the "
                    "reference in double, timed and measured beside twinray's own (docs/plugins.md)")
        ->check(CLI::Validator(
            [](const std::string& name) -> std::string {
                return is_plugin(name) && name.size() > std::string_view("plugin:").size()
                           ? ""
                           : "--tracer here names a plug-in, plugin:PATH (twinray's own tracers all run); got \"" +
                                 name + "\"";
            },
            "plugin:PATH", "plugin"));
}

void add_tracer_option(CLI::App& command, std::string& tracer) {
    std::string help = "Tracer:";
    for (const std::string& name : tracer_names()) {
        help += " " + name + " (" + tracing::tracer_summary(name) + ");";
    }
    help +=
        " or plugin:PATH (a tracer behind include/twinray/tracer.h, its hits shaded by the reference in double; "
        "docs/plugins.md)";
    command.add_option("--tracer", tracer, help)
        ->check(CLI::Validator(
            [](const std::string& name) -> std::string {
                const std::vector<std::string>& names = tracer_names();
                if (std::find(names.begin(), names.end(), name) != names.end() ||
                    (is_plugin(name) && name.size() > std::string_view("plugin:").size())) {
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

void add_accel_option(CLI::App& command, Accel& accel) {
    command
        .add_option_function<std::string>(
            "--accel",
            [&accel](const std::string& name) {
                accel = name == "none" ? Accel::none : name == "bvh" ? Accel::bvh : Accel::automatic;
            },
            "auto (the default: sse builds a BVH where testing every bounded object would cost more than " +
                std::to_string(sse::bvh_crossover) + " sphere tests, or " +
                std::to_string(sse::bvh_crossover_with_secondary_rays) +
                " where a material reflects or transmits, a box counting 2.7, a triangle 6.2, a CSG object its "
                "primitives and 2.2; the reference where they hold more than " +
                std::to_string(reference::bvh_crossover) +
                " primitives), none (every ray tests every object) or bvh; the image is the same")
        ->check(CLI::IsMember({"auto", "none", "bvh"}));
}

}  // namespace twinray::cli
