#include "pov/povray_runner.h"

#include "compare/image_compare.h"

#include <sys/wait.h>
#include <unistd.h>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>

namespace twinray::pov {
namespace {

namespace fs = std::filesystem;

std::string quoted(const fs::path& path) {
    std::string text = "'";
    for (char c : path.string()) {
        text += c == '\'' ? std::string("'\\''") : std::string(1, c);
    }
    return text + "'";
}

std::string text_of(const fs::path& file) {
    std::ifstream stream(file);
    return {std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
}

std::string tail_of(const fs::path& file, std::size_t characters) {
    std::string text = text_of(file);
    return text.size() > characters ? "..." + text.substr(text.size() - characters) : text;
}

// The CPU seconds POV-Ray's statistics give for `phase` ("Parse Time:", ...): the number before
// " CPU-seconds total" on the lines after it, as in
//   Trace Time:       0 hours  0 minutes  0 seconds (0.621 seconds)
//               using 1 thread(s) with 0.618 CPU-seconds total
std::optional<double> cpu_seconds_of(const std::string& log, const std::string& phase) {
    std::size_t at = log.find(phase);
    if (at == std::string::npos) {
        return std::nullopt;
    }
    std::size_t with = log.find(" with ", at);
    std::size_t total = log.find(" CPU-seconds total", at);
    if (with == std::string::npos || total == std::string::npos || with > total) {
        return std::nullopt;
    }
    try {
        std::size_t used = 0;
        std::string number = log.substr(with + 6, total - with - 6);
        double seconds = std::stod(number, &used);
        return used == number.size() && seconds >= 0 ? std::optional<double>(seconds) : std::nullopt;
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

}  // namespace

std::optional<fs::path> find_povray() {
    const char* path = std::getenv("PATH");
    std::stringstream folders(path != nullptr ? path : "");
    std::string folder;
    while (std::getline(folders, folder, ':')) {
        fs::path candidate = fs::path(folder.empty() ? "." : folder) / "povray";
        if (::access(candidate.c_str(), X_OK) == 0 && !fs::is_directory(candidate)) {
            return candidate;
        }
    }
    return std::nullopt;
}

Image render_with_povray(const fs::path& povray, const fs::path& folder, const std::string& name,
                         const std::string& pov_text, int width, int height, int threads,
                         PovrayStatistics* statistics) {
    // Absolute: the command runs POV-Ray from inside the folder, and its log is written from there too.
    const fs::path where = fs::absolute(folder);
    fs::path scene = where / (name + ".pov");
    fs::path image = where / (name + ".png");
    fs::path log = where / (name + ".log");
    fs::path ini = where / "empty.ini";
    std::ofstream(scene) << pov_text;
    std::ofstream(ini).flush();
    std::string command = "cd " + quoted(where) + " && POVINI=" + quoted(ini) + " " + quoted(povray) + " +I" +
                          quoted(scene) + " +O" + quoted(image) + " +W" + std::to_string(width) + " +H" +
                          std::to_string(height) + " -D -A -UA +FN8 File_Gamma=1.0 +WT" + std::to_string(threads) +
                          (statistics != nullptr ? " +GS" : " -GS") + " -GR -GD > " + quoted(log) + " 2>&1";
    int status = std::system(command.c_str());
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !fs::exists(image)) {
        throw PovrayError("povray failed on " + scene.string() + " (status " + std::to_string(status) + "); its log " +
                          log.string() + " ends:\n" + tail_of(log, 2000));
    }
    if (statistics != nullptr) {
        std::string text = text_of(log);
        std::optional<double> parse = cpu_seconds_of(text, "Parse Time:");
        std::optional<double> bounding = cpu_seconds_of(text, "Bounding Time:");
        std::optional<double> trace = cpu_seconds_of(text, "Trace Time:");
        if (!parse || !bounding || !trace) {
            throw PovrayError("povray's log " + log.string() +
                              " lacks the CPU seconds of its parse, bounding or trace (statistics, +GS); it ends:\n" +
                              tail_of(log, 2000));
        }
        *statistics = {*parse, *bounding, *trace};
    }
    return compare::read_image(image);
}

}  // namespace twinray::pov
