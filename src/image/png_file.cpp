#include "image/png_file.h"

#include "image/image_file.h"
#include "io/file_handle.h"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace twinray {
namespace {

// libpng reports errors by longjmp; its message is kept here and thrown once back in C++ frames, so
// that no C++ object is skipped by the jump.
struct PngErrors {
    std::string message;
};

[[noreturn]] void on_png_error(png_structp png, png_const_charp message) {
    static_cast<PngErrors*>(png_get_error_ptr(png))->message = message;
    png_longjmp(png, 1);
}

void on_png_warning(png_structp, png_const_charp) {}

// libpng's own stdio writer reports a failed write as "Write Error"; this one gives the system's reason.
void write_to_stream(png_structp png, png_bytep bytes, png_size_t count) {
    if (std::fwrite(bytes, 1, count, static_cast<std::FILE*>(png_get_io_ptr(png))) != count) {
        char reason[160];  // not a std::string: png_error jumps over this frame
        std::snprintf(reason, sizeof reason, "write failed: %s", std::strerror(errno));
        png_error(png, reason);
    }
}

void flush_stream(png_structp png) {
    std::fflush(static_cast<std::FILE*>(png_get_io_ptr(png)));
}

std::vector<png_byte> to_8bit_rows(const Image& image) {
    std::vector<png_byte> bytes;
    bytes.reserve(image.pixels().size() * 3);
    for (const Rgb& pixel : image.pixels()) {
        bytes.push_back(quantize_8bit(pixel.r));
        bytes.push_back(quantize_8bit(pixel.g));
        bytes.push_back(quantize_8bit(pixel.b));
    }
    return bytes;
}

std::vector<png_bytep> row_pointers(png_bytep first, std::size_t row_bytes, int height) {
    std::vector<png_bytep> rows(static_cast<std::size_t>(height));
    for (std::size_t y = 0; y < rows.size(); ++y) {
        rows[y] = first + y * row_bytes;
    }
    return rows;
}

// The libpng calls of one write, with nothing to destroy between setjmp and its longjmp.
bool write_rows(png_structp png, png_infop info, const Image& image, std::FILE* stream, png_bytepp rows) {
    if (setjmp(png_jmpbuf(png))) {
        return false;
    }
    png_set_write_fn(png, stream, write_to_stream, flush_stream);
    // One filter instead of libpng's trial of all five per row: a quarter faster on rendered images,
    // for files as small (spheres.png: 20108 bytes against 20482).
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
    png_set_IHDR(png, info, static_cast<png_uint_32>(image.width()), static_cast<png_uint_32>(image.height()), 8,
                 PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, nullptr);
    return true;
}

// What a PNG holds once libpng's transforms have made every sample 8 or 16 bits, one per channel.
struct PngLayout {
    png_uint_32 width = 0, height = 0;
    int channels = 0;
    int bit_depth = 0;
};

// Reads the header, sets the transforms and checks the size before anything is allocated.
bool read_layout(png_structp png, png_infop info, std::FILE* stream, std::int64_t pixel_limit, PngLayout& layout,
                 std::string& refusal) {
    if (setjmp(png_jmpbuf(png))) {
        return false;
    }
    png_init_io(png, stream);
    png_read_info(png, info);
    layout.width = png_get_image_width(png, info);
    layout.height = png_get_image_height(png, info);
    const std::int64_t pixel_count = std::int64_t{layout.width} * layout.height;
    if (pixel_count > pixel_limit) {
        refusal = std::to_string(layout.width) + " x " + std::to_string(layout.height) + " is " +
                  std::to_string(pixel_count) + " pixels, more than the limit of " + std::to_string(pixel_limit);
        return true;
    }
    png_set_expand(png);  // palettes to RGB, grey of 1, 2 or 4 bits to 8, transparency to alpha
    if (png_get_bit_depth(png, info) == 16) {
        png_set_swap(png);  // 16-bit samples in this machine's byte order
    }
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    layout.channels = png_get_channels(png, info);
    layout.bit_depth = png_get_bit_depth(png, info);
    return true;
}

bool read_rows(png_structp png, png_infop info, png_bytepp rows) {
    if (setjmp(png_jmpbuf(png))) {
        return false;
    }
    png_read_image(png, rows);
    png_read_end(png, info);
    return true;
}

// Grey (with or without alpha) is one channel expanded to three; RGB(A) keeps its first three.
template <class Sample>
Image to_image(const png_byte* samples, const PngLayout& layout, float scale) {
    Image image(static_cast<int>(layout.width), static_cast<int>(layout.height));
    const auto channels = static_cast<std::size_t>(layout.channels);
    auto component = [&](std::size_t pixel, std::size_t channel) {
        Sample value;
        std::memcpy(&value, samples + (pixel * channels + channel) * sizeof value, sizeof value);
        return static_cast<float>(value) * scale;
    };
    std::size_t pixel = 0;
    for (int y = 0; y < image.height(); ++y) {
        for (int x = 0; x < image.width(); ++x, ++pixel) {
            const float first = component(pixel, 0);
            image.at(x, y) =
                channels < 3 ? Rgb{first, first, first} : Rgb{first, component(pixel, 1), component(pixel, 2)};
        }
    }
    return image;
}

}  // namespace

void write_png(const Image& image, std::FILE* stream) {
    PngErrors errors;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &errors, on_png_error, on_png_warning);
    if (!png) {
        throw std::runtime_error("libpng cannot start a write");
    }
    png_infop info = png_create_info_struct(png);
    std::vector<png_byte> bytes = to_8bit_rows(image);
    std::vector<png_bytep> rows =
        row_pointers(bytes.data(), static_cast<std::size_t>(image.width()) * 3, image.height());
    const bool written = info && write_rows(png, info, image, stream, rows.data());
    png_destroy_write_struct(&png, &info);
    if (!written) {
        throw std::runtime_error(errors.message.empty() ? "libpng cannot start a write" : errors.message);
    }
}

Image read_png(const std::filesystem::path& path, std::int64_t pixel_limit) {
    const io::FileHandle stream(std::fopen(path.c_str(), "rb"));
    if (!stream) {
        throw std::runtime_error(std::strerror(errno));
    }
    png_byte signature[8] = {};
    if (std::fread(signature, 1, sizeof signature, stream.get()) != sizeof signature ||
        png_sig_cmp(signature, 0, sizeof signature) != 0) {
        throw std::runtime_error("Not a PNG file");
    }
    PngErrors errors;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &errors, on_png_error, on_png_warning);
    if (!png) {
        throw std::runtime_error("libpng cannot start a read");
    }
    png_infop info = png_create_info_struct(png);
    png_set_sig_bytes(png, sizeof signature);
    PngLayout layout;
    std::string refusal;
    bool read = info && read_layout(png, info, stream.get(), pixel_limit, layout, refusal);
    std::unique_ptr<png_byte[]> samples;
    if (read && refusal.empty()) {
        const std::size_t row_bytes = std::size_t{layout.width} * static_cast<std::size_t>(layout.channels) *
                                      static_cast<std::size_t>(layout.bit_depth / 8);
        // Not zero-filled: a truncated file that claims 8192 x 8192 fails without touching 384 MiB first.
        samples = std::make_unique_for_overwrite<png_byte[]>(row_bytes * layout.height);
        std::vector<png_bytep> rows = row_pointers(samples.get(), row_bytes, static_cast<int>(layout.height));
        read = read_rows(png, info, rows.data());
    }
    png_destroy_read_struct(&png, &info, nullptr);
    if (!read) {
        throw std::runtime_error(errors.message.empty() ? "libpng cannot start a read" : errors.message);
    }
    if (!refusal.empty()) {
        throw std::runtime_error(refusal);
    }
    return layout.bit_depth == 16 ? to_image<std::uint16_t>(samples.get(), layout, 1.0f / 65535)
                                  : to_image<png_byte>(samples.get(), layout, 1.0f / 255);
}

}  // namespace twinray
