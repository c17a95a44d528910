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

// OpenEXR 3.1 allocates each header attribute at the size the file claims before it reads the value, so
// a few hundred mutated bytes can claim gigabytes: ~1.9 GB and seconds per input, which held the rate
// at 2 inputs/s (tests/data/fuzz_regressions/image_loader/ keeps one; docs/reliability.md). Such inputs
// are skipped: walking the attribute list (name\0 type\0 int32 size, value) finds them.
bool exr_claims_more_than_it_holds(const std::uint8_t* data, std::size_t size) {
    std::size_t at = 8;  // magic number, version and flags
    while (at < size && data[at] != 0) {
        for (int text = 0; text < 2; ++text) {  // the attribute's name, then its type name
            const void* end = std::memchr(data + at, 0, size - at);
            if (end == nullptr) {
                return false;
            }
            at = static_cast<std::size_t>(static_cast<const std::uint8_t*>(end) - data) + 1;
        }
        if (size - at < 4) {
            return false;
        }
        std::uint32_t claimed = std::uint32_t{data[at]} | std::uint32_t{data[at + 1]} << 8 |
                                std::uint32_t{data[at + 2]} << 16 | std::uint32_t{data[at + 3]} << 24;
        at += 4;
        if (claimed > size - at) {
            return true;
        }
        at += claimed;
    }
    return false;
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
    if (extension == ".exr" && exr_claims_more_than_it_holds(data, size)) {
        return -1;  // not added to the corpus
    }
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
