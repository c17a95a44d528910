#include "cli/watertight_command.h"

#include "accuracy/watertight.h"
#include "cli/exit_codes.h"
#include "io/atomic_file.h"
#include "sse/cpu.h"
#include "sse/tracer.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace twinray::cli {
namespace {

struct WatertightArguments {
    int rays_per_case = 50000;
    std::string csv_path;
};

// A tracer under judgement: its name and, for a case's scene, how it counts crossings.
struct Judged {
    std::string name;
    std::function<accuracy::CrossingCounter(const scene::Scene&)> counter_for;
};

std::vector<Judged> judged_tracers() {
    std::vector<Judged> tracers;
    tracers.push_back({"reference", accuracy::oracle_crossings});
    if (!sse::cpu_supports_sse41()) {
        return tracers;
    }
    for (const sse::Precision& precision : sse::every_built_precision()) {
        if (precision.flush_denormals) {
            continue;
        }
        tracers.push_back({"sse " + sse::precision_name(precision), [precision](const scene::Scene& scene) {
                               return accuracy::sse_crossings(scene, precision);
                           }});
    }
    return tracers;
}

int run_watertight(const WatertightArguments& arguments) {
    std::ostringstream csv;
    csv << "tracer,family,distance,size,rays,misses,double_hits\n";
    // tracer × distance, every family and size summed: the closing table.
    std::map<std::pair<std::string, double>, accuracy::WatertightTally> rows;
    std::vector<std::string> names;
    const auto start = std::chrono::steady_clock::now();
    const std::vector<Judged> tracers = judged_tracers();
    for (const std::string& family : accuracy::watertight_families()) {
        for (double distance : accuracy::watertight_distances()) {
            for (double size : accuracy::watertight_sizes()) {
                accuracy::WatertightCase watertight =
                    accuracy::make_watertight_case(family, distance, size, arguments.rays_per_case);
                for (const Judged& judged : tracers) {
                    accuracy::WatertightTally tally =
                        accuracy::count_watertightness(watertight, judged.counter_for(watertight.scene));
                    csv << judged.name << "," << family << "," << distance << "," << size << "," << tally.rays << ","
                        << tally.misses << "," << tally.double_hits << "\n";
                    accuracy::WatertightTally& row = rows[{judged.name, distance}];
                    row.rays += tally.rays;
                    row.misses += tally.misses;
                    row.double_hits += tally.double_hits;
                    if (std::find(names.begin(), names.end(), judged.name) == names.end()) {
                        names.push_back(judged.name);
                    }
                }
            }
        }
    }
    std::printf("| tracer | distance | rays | misses | double hits |\n|---|---:|---:|---:|---:|\n");
    std::uint64_t failures = 0;
    for (const std::string& name : names) {
        for (double distance : accuracy::watertight_distances()) {
            const accuracy::WatertightTally& row = rows[{name, distance}];
            std::printf("| %s | %g | %llu | %llu | %llu |\n", name.c_str(), distance,
                        static_cast<unsigned long long>(row.rays), static_cast<unsigned long long>(row.misses),
                        static_cast<unsigned long long>(row.double_hits));
            failures += row.misses + row.double_hits;
        }
    }
    std::printf("time: %.1f s; families: sphere, fan, split square, grid; sizes 1e-4 to 1e4\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    if (!arguments.csv_path.empty()) {
        try {
            io::write_text_atomically(arguments.csv_path, csv.str());
        } catch (const std::exception& error) {
            std::cerr << "twinray watertight: " << error.what() << "\n";
            return exit_output_error;
        }
    }
    return failures == 0 ? exit_success : exit_not_watertight;
}

}  // namespace

void add_watertight_command(CLI::App& app, std::function<int()>& run) {
    auto arguments = std::make_shared<WatertightArguments>();
    CLI::App* command = app.add_subcommand(
        "watertight",
        "Rays at the shared edges and vertices of closed meshes, fans and split squares, at distances 1 to 1e7 and "
        "sizes 1e-4 to 1e4: misses and double hits per tracer (exit 0: none, 6: some)");
    command->add_option("--rays", arguments->rays_per_case, "Rays per family, distance and size")
        ->check(CLI::Range(1, 10'000'000))
        ->capture_default_str();
    command->add_option("--csv", arguments->csv_path, "Also write every case's counts here (atomically)");
    command->callback([arguments, &run] { run = [arguments] { return run_watertight(*arguments); }; });
}

}  // namespace twinray::cli
