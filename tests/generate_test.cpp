// `twinray generate`: every family's scene loads with our loader, has the size its rule promises,
// renders with both tracers, and is the same bytes for the same family, size and seed; bad requests
// are refused with the usual statuses and leave nothing behind.
#include "cli/exit_codes.h"
#include "cli/generate_scene.h"
#include "reference/tracer.h"
#include "run_twinray.h"
#include "scene/loader.h"
#include "sse/cpu.h"
#include "sse/tracer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

using twinray::cli::generate_scene;
using twinray::cli::GeneratedScene;
using twinray::cli::max_generated_primitives;
using twinray::test::CommandResult;
using twinray::test::run_twinray;
using twinray::test::RunningTwinray;

const std::vector<std::string> families = {"fractal", "field", "lattice", "csg"};

struct Generated {
    GeneratedScene scene;
    std::string text;
};

Generated generate(const std::string& family, int size, std::uint64_t seed = 1) {
    Generated generated;
    generated.scene = generate_scene(family, size, seed, [&](std::string_view piece) { generated.text.append(piece); });
    return generated;
}

std::string read_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The count nearest `size` among `achievable` (ascending) and not above the maximum; ties to the smaller.
std::int64_t nearest(const std::vector<std::int64_t>& achievable, int size) {
    std::int64_t best = achievable.front();
    for (std::int64_t count : achievable) {
        if (count <= max_generated_primitives && std::llabs(count - size) < std::llabs(best - size)) {
            best = count;
        }
    }
    return best;
}

// The rule of generate_scene.h and docs/performance.md, restated from the documentation, not the code.
std::int64_t promised_primitives(const std::string& family, int size) {
    if (family == "field") {
        return size;
    }
    if (family == "csg") {
        return size == 2 ? 3 : size;
    }
    std::vector<std::int64_t> achievable;
    if (family == "fractal") {
        for (std::int64_t depth = 0, power = 9; depth <= 7; ++depth, power *= 9) {
            achievable.push_back(1 + (power - 1) / 8);  // floor + (9^(depth+1) − 1) / 8 spheres
        }
    } else {
        for (std::int64_t n = 1; n <= 70; ++n) {
            for (auto [a, b, c] : {std::array{n, n, n}, std::array{n, n, n + 1}, std::array{n, n + 1, n + 1}}) {
                achievable.push_back(1 + 4 * a * b * c - a * b - b * c - c * a);
            }
        }
    }
    return nearest(achievable, size);
}

class GenerateTest : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        std::string name = info->name();
        std::replace(name.begin(), name.end(), '/', '_');
        folder_ = fs::path(TWINRAY_TEST_OUTPUT_DIR) / "generate" / name;
        fs::remove_all(folder_);
        fs::create_directories(folder_);
    }
    std::string path(const std::string& name) const { return (folder_ / name).string(); }
    std::vector<std::string> files() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(folder_)) {
            names.push_back(entry.path().filename().string());
        }
        return names;
    }
    fs::path folder_;
};

class EveryFamily : public GenerateTest, public ::testing::WithParamInterface<std::string> {};

INSTANTIATE_TEST_SUITE_P(Families, EveryFamily, ::testing::ValuesIn(families),
                         [](const auto& param_info) { return param_info.param; });

TEST_P(EveryFamily, GeneratedScenesLoadAndHaveTheRequestedSize) {
    for (int size : {1, 2, 3, 10, 11, 99, 1000, 5000, 30000}) {
        Generated generated = generate(GetParam(), size);
        twinray::scene::Scene scene = twinray::scene::parse_scene(generated.text, GetParam());
        EXPECT_EQ(static_cast<std::int64_t>(scene.leaf_paths.size()), generated.scene.primitives) << size;
        EXPECT_EQ(generated.scene.primitives, promised_primitives(GetParam(), size)) << "--size " << size;
    }
}

TEST_P(EveryFamily, GenerateIsByteIdenticalForTheSameSeed) {
    for (const char* name : {"a.json", "b.json"}) {
        CommandResult result = run_twinray("generate " + GetParam() + " --size 500 --seed 7 -o " + path(name));
        ASSERT_EQ(result.exit_status, twinray::cli::exit_success) << result.output;
    }
    std::string written = read_bytes(path("a.json"));
    EXPECT_EQ(written, read_bytes(path("b.json")));
    EXPECT_EQ(written, generate(GetParam(), 500, 7).text) << "the command writes what generate_scene writes";
}

TEST_P(EveryFamily, GenerateReportsHowManyPrimitivesItWrote) {
    CommandResult result = run_twinray("generate " + GetParam() + " --size 100 -o " + path("s.json"));
    ASSERT_EQ(result.exit_status, twinray::cli::exit_success) << result.output;
    std::size_t leaves = twinray::scene::load_scene(path("s.json")).leaf_paths.size();
    EXPECT_NE(result.output.find("wrote " + std::to_string(leaves) + " primitives"), std::string::npos)
        << result.output;
}

// A small scene of each family rendered by reference<double> and the SSE tracer at 40 × 30: the
// family's objects (not only its floor) must show, in the share of pixels that differ from the same
// view of the floor alone.
TEST_P(EveryFamily, GeneratedScenesRenderWithBothTracers) {
    twinray::scene::Scene scene = twinray::scene::parse_scene(generate(GetParam(), 60).text, GetParam());
    // The floor is written first: leaf 0, objects[0].
    twinray::scene::Scene floor_only = scene;
    floor_only.objects.resize(1);
    floor_only.leaf_paths.resize(1);
    floor_only.leaf_materials.resize(1);
    twinray::RenderOptions options;
    options.width = 40;
    options.height = 30;
    options.threads = 1;
    auto share_showing_objects = [&](const twinray::Image& image, const twinray::Image& floor) {
        int differing = 0;
        for (std::size_t i = 0; i < image.pixels().size(); ++i) {
            const twinray::Rgb& a = image.pixels()[i];
            const twinray::Rgb& b = floor.pixels()[i];
            float difference = std::max({std::fabs(a.r - b.r), std::fabs(a.g - b.g), std::fabs(a.b - b.b)});
            differing += difference > 0.02f ? 1 : 0;
        }
        return static_cast<double>(differing) / static_cast<double>(image.pixels().size());
    };
    EXPECT_GT(share_showing_objects(twinray::reference::render<double>(scene, options).image,
                                    twinray::reference::render<double>(floor_only, options).image),
              0.1)
        << "reference<double>";
    if (!twinray::sse::cpu_supports_sse41()) {
        GTEST_SKIP() << "no SSE4.1 on this CPU: the SSE tracer's render is not tested";
    }
    EXPECT_GT(share_showing_objects(twinray::sse::render(scene, options).image,
                                    twinray::sse::render(floor_only, options).image),
              0.1)
        << "sse";
}

// FNV-1a, written out so that the recorded values below mean the same on every platform.
std::uint64_t fnv1a(const std::string& text) {
    std::uint64_t hash = 0xcbf29ce484222325ULL;
    for (unsigned char byte : text) {
        hash = (hash ^ byte) * 0x100000001b3ULL;
    }
    return hash;
}

// The same request gives the same file on any x86-64 machine, compiler and standard library: these
// are the bytes of g++ 12 and libstdc++ on Debian 12. A deliberate change to a family changes them:
// update the values with the change, and say so in its commit.
TEST_F(GenerateTest, GeneratedFilesAreTheRecordedBytes) {
    const std::vector<std::pair<std::string, std::uint64_t>> recorded = {
        {"fractal", 0xd8588e66c5435676ULL},
        {"field", 0x1c91f0708718db69ULL},
        {"lattice", 0x297d443de9126fe9ULL},
        {"csg", 0x8522c9de8f2ae505ULL},
    };
    for (const auto& [family, hash] : recorded) {
        EXPECT_EQ(fnv1a(generate(family, 300, 1).text), hash) << family;
    }
}

TEST_F(GenerateTest, DifferentSeedsGiveDifferentFields) {
    for (const char* family : {"field", "csg"}) {
        Generated one = generate(family, 400, 1);
        Generated two = generate(family, 400, 2);
        EXPECT_NE(one.text, two.text) << family;
        EXPECT_EQ(one.scene.primitives, two.scene.primitives) << family;
    }
}

TEST_F(GenerateTest, NumbersAreWrittenOnTheGridInTheirShortestForm) {
    std::string text;
    twinray::cli::SceneTextWriter out([&](std::string_view piece) { text.append(piece); }, 3);
    twinray::scene::Scene header;
    header.camera = {{0, 1, 5}, {0, 0, 0}, {0, 1, 0}, 50};
    out.begin(header);
    out.sphere({0.1, -0.00004, 2.0000004}, 1.0 / 3);
    out.box({-1e-9, 1234.5678, -7}, {1, 1234.6, 0.25});
    out.end();
    EXPECT_NE(text.find(R"({"type": "sphere", "center": [0.1, 0, 2], "radius": 0.333})"), std::string::npos) << text;
    EXPECT_NE(text.find(R"({"type": "box", "min": [0, 1234.568, -7], "max": [1, 1234.6, 0.25]})"), std::string::npos)
        << text;
    EXPECT_EQ(twinray::scene::parse_scene(text, "<written>").leaf_paths.size(), 2u);
}

TEST_F(GenerateTest, GenerateRefusesUnknownFamilyWithExitCode) {
    CommandResult result = run_twinray("generate sphereflake -o " + path("s.json"));
    EXPECT_EQ(result.exit_status, twinray::cli::exit_usage) << result.output;
    for (const std::string& family : families) {
        EXPECT_NE(result.output.find(family), std::string::npos) << "the message lists the families:\n"
                                                                 << result.output;
    }
    EXPECT_TRUE(files().empty());
}

TEST_F(GenerateTest, GenerateRefusesSizesOutsideOneToTheMaximum) {
    for (const char* size : {"0", "-3", "1000001", "many"}) {
        CommandResult result = run_twinray(std::string("generate field --size ") + size + " -o " + path("s.json"));
        EXPECT_EQ(result.exit_status, twinray::cli::exit_usage) << size << ": " << result.output;
        EXPECT_NE(result.output.find("--size"), std::string::npos) << result.output;
    }
    EXPECT_TRUE(files().empty());
}

TEST_F(GenerateTest, GenerateRefusesSeedsThatAreNotWhole64BitNumbers) {
    for (const char* seed : {"-1", "18446744073709551616", "1.5", "x"}) {
        CommandResult result = run_twinray(std::string("generate field --seed ") + seed + " -o " + path("s.json"));
        EXPECT_EQ(result.exit_status, twinray::cli::exit_usage) << seed << ": " << result.output;
        EXPECT_NE(result.output.find("0..18446744073709551615"), std::string::npos) << result.output;
    }
    EXPECT_TRUE(files().empty());
    CommandResult largest = run_twinray("generate field --seed 18446744073709551615 --size 10 -o " + path("s.json"));
    EXPECT_EQ(largest.exit_status, twinray::cli::exit_success) << largest.output;
}

TEST_F(GenerateTest, GenerateIntoAMissingFolderFailsWithStatusThree) {
    CommandResult result = run_twinray("generate lattice -o " + path("missing/s.json"));
    EXPECT_EQ(result.exit_status, twinray::cli::exit_output_error) << result.output;
    EXPECT_NE(result.output.find("does not exist"), std::string::npos) << result.output;
}

// A full disk part-way through (RLIMIT_FSIZE, as failure_test's DiskFullTest): status 3, the old file
// kept, no temporary left.
TEST_F(GenerateTest, GenerateFailingPartWayKeepsTheOldFileAndLeavesNoTemporary) {
    std::ofstream(path("s.json")) << "the old scene";
    RunningTwinray generate_process({"generate", "field", "--size", "100000", "-o", path("s.json")},
                                    {.file_size_bytes = 64 * 1024});
    CommandResult result = generate_process.wait();
    EXPECT_EQ(result.exit_status, twinray::cli::exit_output_error) << result.output;
    EXPECT_NE(result.output.find("File too large"), std::string::npos) << result.output;
    EXPECT_EQ(read_bytes(path("s.json")), "the old scene");
    EXPECT_EQ(files(), std::vector<std::string>{"s.json"});
}

// The largest size is streamed, never held: a million primitives (about 100 MB of text) in the
// memory of a small one.
TEST_F(GenerateTest, GenerateWritesTheLargestSizeInLittleMemory) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
    GTEST_SKIP() << "a sanitizer's shadow memory is not the program's: the budget holds for uninstrumented builds";
#endif
    RunningTwinray generate_process(
        {"generate", "csg", "--size", std::to_string(max_generated_primitives), "-o", path("s.json")});
    CommandResult result = generate_process.wait();
    ASSERT_EQ(result.exit_status, twinray::cli::exit_success) << result.output;
    EXPECT_NE(result.output.find("wrote 1000000 primitives"), std::string::npos) << result.output;
    EXPECT_GT(fs::file_size(path("s.json")), 50'000'000u);
    EXPECT_LT(generate_process.peak_memory_bytes(), 32L << 20);
}

}  // namespace
