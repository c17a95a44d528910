#include "image/exr_file.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfOutputFile.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace twinray {
namespace {

// OpenEXR writes through this onto the caller's stream, whose error flag, flush and close the caller
// checks: OpenEXR's OutputFile writes its offset table in its destructor, where it swallows errors.
class StdioOutput final : public Imf::OStream {
public:
    explicit StdioOutput(std::FILE* stream) : Imf::OStream("output"), stream_(stream) {}

    void write(const char bytes[], int count) override {
        if (std::fwrite(bytes, 1, static_cast<std::size_t>(count), stream_) != static_cast<std::size_t>(count)) {
            throw std::runtime_error(std::string("write failed: ") + std::strerror(errno));
        }
    }

    uint64_t tellp() override { return static_cast<uint64_t>(ftello(stream_)); }

    void seekp(uint64_t position) override {
        if (fseeko(stream_, static_cast<off_t>(position), SEEK_SET) != 0) {
            throw std::runtime_error(std::string("write failed: ") + std::strerror(errno));
        }
    }

private:
    std::FILE* stream_;
};

// Little-endian, as every number in an EXR file.
std::int64_t little_endian(const unsigned char* bytes, int count) {
    std::uint64_t value = 0;
    for (int i = count - 1; i >= 0; --i) {
        value = value << 8 | bytes[i];
    }
    return static_cast<std::int64_t>(value);
}

std::int32_t signed_32(const unsigned char* bytes) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(little_endian(bytes, 4)));
}

void refuse_pixels_over(std::int64_t width, std::int64_t height, std::int64_t pixel_limit, const std::string& what) {
    // Each side is checked alone first, so that the product cannot overflow.
    if (width < 1 || height < 1 || width > pixel_limit || height > pixel_limit || width * height > pixel_limit) {
        throw std::runtime_error("its header claims " + what + " of " + std::to_string(width) + " x " +
                                 std::to_string(height) + " pixels; allowed: 1 to " + std::to_string(pixel_limit) +
                                 " pixels");
    }
}

// The attributes OpenEXR requires of every part's header.
constexpr const char* required_attributes[] = {"channels",           "compression",      "dataWindow",
                                               "displayWindow",      "lineOrder",        "pixelAspectRatio",
                                               "screenWindowCenter", "screenWindowWidth"};

}  // namespace

void check_exr_header_claims(const std::filesystem::path& path, std::int64_t pixel_limit) {
    std::ifstream file(path, std::ios::binary);
    std::error_code size_error;
    const std::uintmax_t file_size = std::filesystem::file_size(path, size_error);
    if (!file || size_error) {
        throw std::runtime_error("cannot open it");
    }
    auto truncated = [] { return std::runtime_error("its header ends before the file does (not an OpenEXR file?)"); };
    std::array<unsigned char, 8> start{};
    if (!file.read(reinterpret_cast<char*>(start.data()), start.size())) {
        throw truncated();
    }
    const bool multipart = (little_endian(start.data() + 4, 4) & 0x1000) != 0;
    // A name or type name holds at most 255 characters (long-name flag) and its terminating zero.
    auto read_text = [&] {
        std::string text;
        if (!std::getline(file, text, '\0') || text.size() > 255) {
            throw truncated();
        }
        return text;
    };
    const bool single_part_tiled = (little_endian(start.data() + 4, 4) & 0x200) != 0;
    for (bool first_part = true;; first_part = false) {
        if (!first_part && (!multipart || file.peek() == 0)) {
            return;  // a single part's header, or the empty header closing a multi-part file's list
        }
        // The attributes OpenEXR requires of every part (and of a single-part tiled file, its tiles).
        // Without them OpenEXR 3.1 goes on with defaults: an 860-byte tiled file lacking its data window
        // and tile description took over 30 s to read (fuzz, slow-unit-c5df5a60).
        std::vector<std::string> missing(std::begin(required_attributes), std::end(required_attributes));
        if (single_part_tiled) {
            missing.push_back("tiles");
        }
        while (file.peek() != 0) {
            const std::string name = read_text();
            const std::string type = read_text();
            missing.erase(std::remove(missing.begin(), missing.end(), name), missing.end());
            std::array<unsigned char, 16> value{};
            if (!file.read(reinterpret_cast<char*>(value.data()), 4)) {
                throw truncated();
            }
            const std::int64_t size = signed_32(value.data());
            const std::int64_t left = static_cast<std::int64_t>(file_size) - static_cast<std::int64_t>(file.tellg());
            if (size < 0 || size > left) {
                throw std::runtime_error("its header's attribute '" + name + "' claims " + std::to_string(size) +
                                         " bytes, more than the " + std::to_string(left) + " left in the file");
            }
            const std::int64_t kept = std::min<std::int64_t>(size, static_cast<std::int64_t>(value.size()));
            file.read(reinterpret_cast<char*>(value.data()), kept);
            file.seekg(size - kept, std::ios::cur);
            if (!file) {
                throw truncated();
            }
            if (type == "tiledesc" && size >= 8) {
                refuse_pixels_over(little_endian(value.data(), 4), little_endian(value.data() + 4, 4), pixel_limit,
                                   "tiles");
            } else if (type == "box2i" && size == 16 && name == "dataWindow") {
                refuse_pixels_over(std::int64_t{signed_32(value.data() + 8)} - signed_32(value.data()) + 1,
                                   std::int64_t{signed_32(value.data() + 12)} - signed_32(value.data() + 4) + 1,
                                   pixel_limit, "a data window");
            }
        }
        if (!missing.empty()) {
            std::string all;
            for (const char* attribute : required_attributes) {
                all += std::string(attribute) + ", ";
            }
            throw std::runtime_error("its header lacks the attribute '" + missing.front() +
                                     "', which OpenEXR requires (" + all + "and tiles in a tiled file)");
        }
        file.get();  // the zero that ends this part's header
    }
}

void write_exr(const Image& image, std::FILE* stream) {
    static_assert(sizeof(Rgb) == 3 * sizeof(float), "Rgb must be three packed floats for OpenEXR");
    Imf::Header header(image.width(), image.height());
    header.compression() = Imf::ZIP_COMPRESSION;
    // zlib's fastest level rather than OpenEXR's default 4: 5 ms less of a 320 x 240 render's 40 ms
    // process here, for a file 2% larger (spheres.exr: 180307 bytes against 176693).
    header.zipCompressionLevel() = 1;
    Imf::FrameBuffer frame;
    // OpenEXR's slices take a writable pointer but only read from it when writing.
    char* first = reinterpret_cast<char*>(const_cast<Rgb*>(image.pixels().data()));
    const std::size_t pixel_bytes = sizeof(Rgb);
    const std::size_t row_bytes = pixel_bytes * static_cast<std::size_t>(image.width());
    const char* names[] = {"R", "G", "B"};
    for (std::size_t channel = 0; channel < 3; ++channel) {
        header.channels().insert(names[channel], Imf::Channel(Imf::FLOAT));
        frame.insert(names[channel], Imf::Slice(Imf::FLOAT, first + channel * sizeof(float), pixel_bytes, row_bytes));
    }
    StdioOutput output(stream);
    Imf::OutputFile file(output, header);
    file.setFrameBuffer(frame);
    file.writePixels(image.height());
}

}  // namespace twinray
