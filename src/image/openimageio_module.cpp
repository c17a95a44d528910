#include "image/openimageio_module.h"

#include "io/shared_module.h"

#include <stdexcept>
#include <string>

namespace twinray {
namespace {

// The module installed beside twinray, else in this build tree (both paths set by src/CMakeLists.txt).
const OpenImageIoFunctions& load_module() {
    return io::load_shared_module<OpenImageIoFunctions>(
        io::installed_or_built(TWINRAY_OPENIMAGEIO_MODULE_INSTALLED, TWINRAY_OPENIMAGEIO_MODULE).c_str(),
        "twinray_openimageio_functions", "the OpenImageIO module");
}

// Loaded once per process, by whichever thread asks first; a failed load is retried on the next call.
const OpenImageIoFunctions& module_functions() {
    static const OpenImageIoFunctions& functions = load_module();
    return functions;
}

}  // namespace

Image read_with_openimageio(const std::filesystem::path& path, std::int64_t pixel_limit) {
    return module_functions().read(path, pixel_limit);
}

Image inferno_colour_map(const Image& grey) {
    return module_functions().inferno(grey);
}

}  // namespace twinray
