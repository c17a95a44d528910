#include "cli/generate_command.h"

#include "cli/exit_codes.h"
#include "cli/generate/mesh_file_writer.h"
#include "cli/generate_scene.h"
#include "io/atomic_file.h"

#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

namespace twinray::cli {
namespace {

namespace fs = std::filesystem;

struct GenerateArguments {
    std::string family;
    int size = default_generated_primitives;
    std::uint64_t seed = 1;
    std::string output_path;
    std::string mesh_file_format;  // empty: the mesh inline
};

// The mesh file beside the scene: its name with the format's extension (big.json, big.obj).
fs::path mesh_file_path(const fs::path& scene, const std::string& format) {
    return fs::path(scene).replace_extension("." + format);
}

// Empty if `text` is a whole number 0..2^64-1, written in decimal digits only; else why not. CLI11's own
// conversion would take "-1" as 2^64 - 1 and 2^64 as 2^64 - 1.
std::string seed_problem(const std::string& text) {
    std::uint64_t seed = 0;
    auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), seed);
    if (text.empty() || error != std::errc{} || end != text.data() + text.size()) {
        return "the seed must be a whole number 0..18446744073709551615, got \"" + text + "\"";
    }
    return "";
}

int run_generate(const GenerateArguments& arguments) {
    const fs::path output = arguments.output_path;
    if (std::string problem = io::output_folder_problem(output); !problem.empty()) {
        std::cerr << "twinray generate: cannot write " << output.string() << ": " << problem << "\n";
        return exit_output_error;
    }
    const std::string& format = arguments.mesh_file_format;
    const fs::path mesh_file = format.empty() ? fs::path() : mesh_file_path(output, format);
    if (!format.empty() && !is_mesh_family(arguments.family)) {
        std::cerr << "twinray generate: --mesh-file applies to the mesh families (sphere-mesh, torus-mesh, tetra, "
                     "sombrero, triangle-soup, mount, gears); "
                  << arguments.family << " writes no mesh\n";
        return exit_usage;
    }
    if (!format.empty() && mesh_file == output) {
        std::cerr << "twinray generate: the scene " << output.string() << " and its mesh file would be one file; "
                  << "name the scene with another extension (e.g. .json)\n";
        return exit_usage;
    }
    SceneSink sink;
    std::FILE* scene_stream = nullptr;
    sink.text = [&scene_stream](std::string_view text) {
        // Stop at the first failed write (a full disk) rather than stream the rest into it.
        if (std::fwrite(text.data(), 1, text.size(), scene_stream) != text.size()) {
            throw std::system_error(errno, std::generic_category());
        }
    };
    bool wrote_mesh_file = false;
    if (!format.empty()) {
        sink.mesh_file = [&](const MeshLists& lists, MeshCounts counts) {
            io::write_stream_atomically(
                mesh_file, [&](std::FILE* stream) { generate::write_mesh_file(stream, format, lists, counts); });
            wrote_mesh_file = true;
            return mesh_file.filename().string();
        };
    }
    GeneratedScene generated;
    try {
        io::write_stream_atomically(output, [&](std::FILE* stream) {
            scene_stream = stream;
            generated = generate_scene(arguments.family, arguments.size, arguments.seed, sink);
        });
    } catch (const io::FileWriteError& error) {
        // A mesh file without the scene that names it would be half of the output.
        if (wrote_mesh_file) {
            std::error_code ignored;
            fs::remove(mesh_file, ignored);
        }
        std::cerr << "twinray generate: " << error.what() << "\n";
        return exit_output_error;
    }
    std::cerr << "twinray generate: wrote " << generated.primitives << " primitives (" << arguments.family << ", "
              << generated.structure << ", seed " << arguments.seed << "; asked for " << arguments.size << ") to "
              << output.string() << (wrote_mesh_file ? ", its mesh to " + mesh_file.string() : "") << "\n";
    return exit_success;
}

}  // namespace

void add_generate_command(CLI::App& app, std::function<int()>& run) {
    auto arguments = std::make_shared<GenerateArguments>();
    CLI::App* command = app.add_subcommand(
        "generate",
        "Write a large generated scene (twinray-scene/1), the same bytes for the same family, size and seed:\n" +
            generated_families_help());
    command->add_option("family", arguments->family, generated_family_list())
        ->required()
        ->check(CLI::IsMember(generated_family_names()));
    command
        ->add_option("--size", arguments->size,
                     "Target number of primitives (leaves), of triangles for a mesh family, 1.." +
                         std::to_string(max_generated_primitives))
        ->check(CLI::Range(1, max_generated_primitives))
        ->capture_default_str();
    command->add_option("--seed", arguments->seed, "Seed of the family's random choices, 0..2^64-1")
        ->check(CLI::Validator(seed_problem, "0..2^64-1"))
        ->capture_default_str();
    command->add_option("-o,--output", arguments->output_path, "Scene file to write (JSON)")->required();
    command
        ->add_option("--mesh-file", arguments->mesh_file_format,
                     "Write a mesh family's mesh to a file beside the scene (the scene's name with the extension\n"
                     "obj or ply: Wavefront OBJ text, or binary PLY of doubles), the same doubles as inline")
        ->check(CLI::IsMember(generate::mesh_file_formats()));
    command->callback([arguments, &run] { run = [arguments] { return run_generate(*arguments); }; });
}

}  // namespace twinray::cli
