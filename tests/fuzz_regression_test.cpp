// Replays every input that ever broke a fuzz target (tests/data/fuzz_regressions/<target>/, see its
// README): each must be accepted or refused with the documented error type, never crash, throw anything
// else or hang; the BVH differential target's inputs (and seeds) must get the same answers with and without
// the BVHs. Under the asan-ubsan preset the replay also checks memory and undefined behaviour, as the
// fuzzer did.
#include "compare/image_compare.h"
#include "scene/loader.h"
#include "scene/mesh_file.h"
#include "tests/fuzz/bvh_differential.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::vector<fs::path> files_in(const fs::path& folder) {
    std::vector<fs::path> inputs;
    if (fs::is_directory(folder)) {
        for (const auto& entry : fs::directory_iterator(folder)) {
            if (entry.is_regular_file()) {
                inputs.push_back(entry.path());
            }
        }
    }
    return inputs;
}

std::vector<fs::path> recorded_inputs(const std::string& target) {
    return files_in(fs::path(TWINRAY_SOURCE_DIR) / "tests" / "data" / "fuzz_regressions" / target);
}

std::string read_bytes(const fs::path& file) {
    std::ifstream stream(file, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(stream)), std::istreambuf_iterator<char>());
}

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

TEST(FuzzRegression, EverySceneInputIsAcceptedOrRefusedWithASceneErrorWithinASecond) {
    std::vector<fs::path> inputs = recorded_inputs("scene_loader");
    if (inputs.empty()) {
        GTEST_SKIP() << "no scene loader input has failed a fuzz run (tests/data/fuzz_regressions/scene_loader/)";
    }
    for (const fs::path& input : inputs) {
        SCOPED_TRACE(input.filename().string());
        std::string bytes = read_bytes(input);
        auto start = std::chrono::steady_clock::now();
        try {
            twinray::scene::parse_scene(bytes, input.filename().string());
        } catch (const twinray::scene::SceneError& refusal) {
            EXPECT_FALSE(refusal.problem().empty()) << "a refusal says what is wrong";
        } catch (const std::exception& error) {
            ADD_FAILURE() << "refused with something other than a SceneError: " << error.what();
        }
        EXPECT_LT(seconds_since(start), 1.0);
    }
}

// AddressSanitizer's allocator serves OpenEXR's gigabyte allocations several times slower (68 s against the
// uninstrumented build's 35 s at most, measured in a clean-clone CI run): a hang is still a hang at 3×.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr double sanitizer_slowdown = 3;
#else
constexpr double sanitizer_slowdown = 1;
#endif

// Sixty seconds, the image fuzz target's per-input timeout: the recorded OpenEXR inputs make OpenEXR
// allocate gigabytes, 2–35 s a read. Measured in this process's CPU time, what a hang would burn: wall time
// also counts whatever else the machine runs, and missed the limit on a busy 2-core machine.
TEST(FuzzRegression, EveryImageInputIsReadOrRefusedWithAnErrorNamingTheFileWithinSixtySeconds) {
    std::vector<fs::path> inputs = recorded_inputs("image_loader");
    ASSERT_FALSE(inputs.empty()) << "tests/data/fuzz_regressions/image_loader/ holds the OpenEXR input";
    for (const fs::path& input : inputs) {
        SCOPED_TRACE(input.filename().string());
        std::clock_t start = std::clock();
        try {
            twinray::Image image = twinray::compare::read_image(input);
            EXPECT_GE(image.width(), 1);
        } catch (const twinray::compare::ImageReadError& refusal) {
            EXPECT_NE(std::string(refusal.what()).find(input.string()), std::string::npos) << refusal.what();
        } catch (const std::exception& error) {
            ADD_FAILURE() << "refused with something other than an ImageReadError: " << error.what();
        }
        EXPECT_LT(static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC, 60.0 * sanitizer_slowdown)
            << "CPU seconds";
    }
}

// Mesh inputs (named with the extension that picks their reader) as a render reads them: through the reader
// process, read or refused with a SceneError that names the file. Ten seconds of wall time, the reader's own CPU
// being another process's: the recorded .glb took assimp more than ten before the reader walked its chunks.
TEST(FuzzRegression, EveryMeshFileInputIsReadOrRefusedWithASceneErrorNamingTheFileWithinTenSeconds) {
    std::vector<fs::path> inputs = recorded_inputs("mesh_file");
    ASSERT_FALSE(inputs.empty()) << "tests/data/fuzz_regressions/mesh_file/ holds the .glb input";
    for (const fs::path& input : inputs) {
        SCOPED_TRACE(input.filename().string());
        const auto start = std::chrono::steady_clock::now();
        try {
            const twinray::scene::MeshFileResult read =
                twinray::scene::read_mesh_file(input, twinray::scene::max_scene_primitives);
            EXPECT_FALSE(read.meshes.empty());
        } catch (const twinray::scene::SceneError& refusal) {
            EXPECT_NE(std::string(refusal.what()).find(input.string()), std::string::npos) << refusal.what();
        } catch (const std::exception& error) {
            ADD_FAILURE() << "refused with something other than a SceneError: " << error.what();
        }
        EXPECT_LT(seconds_since(start), 10.0 * sanitizer_slowdown) << "seconds";
    }
}

// The BVH differential target's check (tests/fuzz/bvh_differential.h) on its seeds, each a valid scene the
// loader accepts, and on every input that ever found a difference: the same answers bit for bit with and
// without each tracer's BVH.
TEST(FuzzRegression, EveryBvhDifferentialInputGetsTheSameAnswersWithAndWithoutTheBvh) {
    const std::vector<fs::path> seeds =
        files_in(fs::path(TWINRAY_SOURCE_DIR) / "tests" / "fuzz" / "seeds" / "bvh_differential");
    ASSERT_FALSE(seeds.empty()) << "tests/fuzz/seeds/bvh_differential/ holds the target's seeds";
    std::vector<fs::path> inputs = recorded_inputs("bvh_differential");
    inputs.insert(inputs.end(), seeds.begin(), seeds.end());
    for (const fs::path& input : inputs) {
        SCOPED_TRACE(input.filename().string());
        const std::string bytes = read_bytes(input);
        const twinray::fuzz::DifferentialCase decoded =
            twinray::fuzz::CaseDecoder(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()).decode();
        if (std::find(seeds.begin(), seeds.end(), input) != seeds.end()) {
            EXPECT_NO_THROW(twinray::scene::parse_scene(decoded.scene_text, input.filename().string()));
            EXPECT_FALSE(decoded.rays.empty());
        }
        if (input.filename() == "instanced_pile") {
            EXPECT_NE(decoded.scene_text.find(R"("type": "instance")"), std::string::npos)
                << "the seed that takes instances through the walks holds some";
        }
        if (input.filename() == "solid_instanced_pile") {
            EXPECT_GT(twinray::scene::parse_scene(decoded.scene_text, "solid_instanced_pile").solid_instances.size(),
                      64u)
                << "the seed that takes instances of CSG shapes through the walks holds more than CsgCandidates' 64";
        }
        EXPECT_EQ(twinray::fuzz::first_difference(decoded), "");
    }
}

}  // namespace
