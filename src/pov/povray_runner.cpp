#include "pov/povray_runner.h"

#include "compare/image_compare.h"

#include <sys/wait.h>
#include <unistd.h>
#include <cstdlib>
#include <fstream>
#include <iterator>
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

std::string tail_of(const fs::path& file, std::size_t characters) {
    std::ifstream stream(file);
    std::string text((std::istreambuf_iterator<char>(stream)), std::istreambuf_iterator<char>());
    return text.size() > characters ? "..." + text.substr(text.size() - characters) : text;
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
                         const std::string& pov_text, int width, int height, int threads) {
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
                          " -GS -GR -GD > " + quoted(log) + " 2>&1";
    int status = std::system(command.c_str());
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !fs::exists(image)) {
        throw PovrayError("povray failed on " + scene.string() + " (status " + std::to_string(status) + "); its log " +
                          log.string() + " ends:\n" + tail_of(log, 2000));
    }
    return compare::read_image(image);
}

}  // namespace twinray::pov
