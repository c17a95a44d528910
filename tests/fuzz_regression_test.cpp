// Replays every input that ever broke a fuzz target (tests/data/fuzz_regressions/, see its README):
// the loader must accept it or refuse it with a SceneError, never crash, throw anything else or hang.
// Under the asan-ubsan preset the replay also checks memory and undefined behaviour, as the fuzzer did.
#include "scene/loader.h"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::vector<fs::path> recorded_inputs() {
    std::vector<fs::path> inputs;
    fs::path folder = fs::path(TWINRAY_SOURCE_DIR) / "tests" / "data" / "fuzz_regressions";
    if (fs::is_directory(folder)) {
        for (const auto& entry : fs::directory_iterator(folder)) {
            if (entry.is_regular_file() && entry.path().extension() != ".md") {
                inputs.push_back(entry.path());
            }
        }
    }
    return inputs;
}

TEST(FuzzRegression, EveryRecordedInputIsAcceptedOrRefusedWithASceneErrorWithinASecond) {
    std::vector<fs::path> inputs = recorded_inputs();
    if (inputs.empty()) {
        GTEST_SKIP() << "no fuzzer crash recorded in tests/data/fuzz_regressions/ (none found so far)";
    }
    for (const fs::path& input : inputs) {
        SCOPED_TRACE(input.filename().string());
        std::ifstream stream(input, std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(stream)), std::istreambuf_iterator<char>());
        auto start = std::chrono::steady_clock::now();
        try {
            twinray::scene::parse_scene(bytes, input.filename().string());
        } catch (const twinray::scene::SceneError& refusal) {
            EXPECT_FALSE(refusal.problem().empty()) << "a refusal says what is wrong";
        } catch (const std::exception& error) {
            ADD_FAILURE() << "refused with something other than a SceneError: " << error.what();
        }
        EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
    }
}

}  // namespace
