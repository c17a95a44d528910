// Where a test writes its files: a directory of its own under TWINRAY_TEST_OUTPUT_DIR. ctest runs tests in parallel,
// and a file that two tests write fails at random (one test's rewrite made assimp read another's glTF empty).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

namespace twinray::test {

// TWINRAY_TEST_OUTPUT_DIR/group/Suite.Test, a parameterised test's slashes made underscores.
inline std::filesystem::path own_output_path(const std::string& group) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(info->test_suite_name()) + "." + info->name();
    std::replace(name.begin(), name.end(), '/', '_');
    return std::filesystem::path(TWINRAY_TEST_OUTPUT_DIR) / group / name;
}

// `dir` emptied and made: nothing an earlier run left there is read as this run's.
inline std::filesystem::path fresh_directory(const std::filesystem::path& dir) {
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

}  // namespace twinray::test
