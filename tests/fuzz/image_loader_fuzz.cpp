// libFuzzer target for `twinray compare`'s image loading: arbitrary bytes, saved as a file, into
// twinray::compare::read_image (OpenImageIO underneath).
//
// What it holds the loader to, beyond what ASan and UBSan catch in our code: the only way to refuse a
// file is an ImageReadError that says what is wrong; an accepted image has a size within the limits and
// exactly width × height pixels. Anything else aborts and libFuzzer keeps the input.
// OpenImageIO and the format libraries are Debian's uninstrumented builds: ASan sees their memory errors
// only through the functions it intercepts (memcpy, malloc, ...), and coverage guidance sees only our
// code, so this target is a mutation fuzzer around real PNG and EXR files more than a coverage-guided
// one (docs/reliability.md).
// Built only with -DTWINRAY_FUZZ=ON (preset `fuzz`, clang).
#include "compare/image_compare.h"
#include "promise.h"

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;

// Smaller than twinray's own limit (8192 x 8192): a mutated header easily claims millions of pixels, and
// OpenImageIO's PNG reader zero-fills a buffer of the claimed size (up to 768 MiB) before it finds the
// data truncated. Below this limit every byte goes through the decoders as in `twinray compare`; above
// it the same refusal path runs.
constexpr std::int64_t fuzz_pixel_limit = 512 * 512;

void expect(bool holds, const char* what) {
    twinray::fuzz::expect(holds, "image_loader_fuzz", what);
}

// OpenImageIO picks a reader by the file's extension and falls back to the others by content, as it
// does for a user's file: the name follows the EXR magic number, else ".png" (our default output).
std::string extension_for(const std::uint8_t* data, std::size_t size) {
    static const unsigned char exr_magic[4] = {0x76, 0x2f, 0x31, 0x01};
    return size >= 4 && std::memcmp(data, exr_magic, 4) == 0 ? ".exr" : ".png";
}

// One folder per process, so parallel fuzzing jobs never share a file.
const fs::path& scratch_folder() {
    static const fs::path folder = [] {
        fs::path path = fs::temp_directory_path() / ("twinray_image_fuzz_" + std::to_string(getpid()));
        fs::create_directories(path);
        return path;
    }();
    return folder;
}

}  // namespace

// One thread for OpenImageIO and OpenEXR: their pools' start-up and hand-offs cost more than reading a
// few hundred bytes, and one thread keeps each input's run reproducible.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
    OIIO::attribute("threads", 1);
    OIIO::attribute("exr_threads", 1);
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::string extension = extension_for(data, size);
    // A new name each time: nothing OpenImageIO might remember of a previous file can answer for this one.
    static unsigned long long count = 0;
    fs::path path = scratch_folder() / ("input" + std::to_string(count++) + extension);
    {
        std::ofstream file(path, std::ios::binary);
        file.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
        expect(static_cast<bool>(file), "the scratch file could be written");
    }
    try {
        twinray::Image image = twinray::compare::read_image(path, fuzz_pixel_limit);
        expect(image.width() >= 1 && image.height() >= 1, "an accepted image has pixels");
        expect(std::int64_t{image.width()} * image.height() <= fuzz_pixel_limit,
               "an accepted image is within the pixel limit");
        expect(
            image.pixels().size() == static_cast<std::size_t>(image.width()) * static_cast<std::size_t>(image.height()),
            "an accepted image holds width x height pixels");
    } catch (const twinray::compare::ImageReadError& refusal) {
        expect(std::string(refusal.what()).find(path.string()) != std::string::npos, "a refusal names the file");
    }
    fs::remove(path);
    return 0;
}
