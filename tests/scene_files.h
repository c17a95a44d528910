// Every scene in scenes/, sorted: what the parameterised suites (conformance, golden, pov) run over.
#pragma once

#include <algorithm>
#include <filesystem>
#include <vector>

namespace twinray::test {

inline std::vector<std::filesystem::path> scene_files() {
    std::vector<std::filesystem::path> files;
    for (const auto& entry :
         std::filesystem::directory_iterator(std::filesystem::path(TWINRAY_SOURCE_DIR) / "scenes")) {
        if (entry.path().extension() == ".json") {
            files.push_back(entry.path());
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

}  // namespace twinray::test
