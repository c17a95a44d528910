#include "compare/tolerances.h"

#include <nlohmann/json.hpp>

#include <fstream>
#include <stdexcept>

namespace twinray::compare {
namespace {

using nlohmann::json;

[[noreturn]] void refuse(const std::filesystem::path& file, const std::string& where, const std::string& problem) {
    throw std::runtime_error(file.string() + ": " + where + ": " + problem);
}

double number_at(const json& object, const std::string& key, double fallback, const std::filesystem::path& file,
                 const std::string& where) {
    if (!object.contains(key)) {
        return fallback;
    }
    const json& value = object.at(key);
    if (!value.is_number() || value.get<double>() < 0) {
        refuse(file, where + "." + key, "expected a number >= 0");
    }
    return value.get<double>();
}

Thresholds read_thresholds(const json& object, const Thresholds& base, const std::filesystem::path& file,
                           const std::string& where) {
    if (!object.is_object()) {
        refuse(file, where, "expected an object with fail, fail_percent, hard_fail, warn, warn_percent");
    }
    for (const auto& [key, value] : object.items()) {
        if (key != "fail" && key != "fail_percent" && key != "hard_fail" && key != "warn" && key != "warn_percent") {
            refuse(file, where + "." + key, "unknown key; allowed: fail, fail_percent, hard_fail, warn, warn_percent");
        }
    }
    Thresholds out;
    out.fail = number_at(object, "fail", base.fail, file, where);
    out.fail_percent = number_at(object, "fail_percent", base.fail_percent, file, where);
    out.hard_fail = number_at(object, "hard_fail", base.hard_fail, file, where);
    out.warn = number_at(object, "warn", base.warn, file, where);
    out.warn_percent = number_at(object, "warn_percent", base.warn_percent, file, where);
    return out;
}

SceneTolerances read_entry(const json& object, const SceneTolerances& base, const std::filesystem::path& file,
                           const std::string& where) {
    if (!object.is_object()) {
        refuse(file, where, "expected an object with sse, golden and why");
    }
    SceneTolerances out = base;
    for (const auto& [key, value] : object.items()) {
        if (key == "sse") {
            out.sse = read_thresholds(value, base.sse, file, where + ".sse");
        } else if (key == "golden") {
            out.golden = read_thresholds(value, base.golden, file, where + ".golden");
        } else if (key == "why") {
            if (!value.is_string())
                refuse(file, where + ".why", "expected a string");
            out.why = value.get<std::string>();
        } else {
            refuse(file, where + "." + key, "unknown key; allowed: sse, golden, why");
        }
    }
    return out;
}

}  // namespace

ToleranceManifest ToleranceManifest::defaults() {
    ToleranceManifest manifest;
    manifest.defaults_.sse = Thresholds{1.0 / 255.0, 0.1, 0.5, 1.0 / 255.0, 0.1};
    manifest.defaults_.golden = Thresholds{0.5 / 255.0, 0.01, 1.5 / 255.0, 0.5 / 255.0, 0.0};
    return manifest;
}

ToleranceManifest ToleranceManifest::load(const std::filesystem::path& file) {
    std::ifstream stream(file);
    if (!stream) {
        refuse(file, "(file)", "cannot open");
    }
    json document = json::parse(stream, nullptr, false);
    if (document.is_discarded() || !document.is_object()) {
        refuse(file, "(root)", "not a JSON object");
    }
    ToleranceManifest manifest = defaults();
    for (const auto& [key, value] : document.items()) {
        if (key == "default") {
            manifest.defaults_ = read_entry(value, manifest.defaults_, file, "default");
        } else if (key == "scenes") {
            if (!value.is_object())
                refuse(file, "scenes", "expected an object: scene name -> entry");
            for (const auto& [name, entry] : value.items()) {
                manifest.scenes_[name] = read_entry(entry, manifest.defaults_, file, "scenes." + name);
            }
        } else if (key != "comment") {
            refuse(file, key, "unknown key; allowed: comment, default, scenes");
        }
    }
    return manifest;
}

SceneTolerances ToleranceManifest::for_scene(const std::string& scene_name) const {
    auto found = scenes_.find(scene_name);
    return found == scenes_.end() ? defaults_ : found->second;
}

}  // namespace twinray::compare
