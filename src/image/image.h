// A float RGB image, row-major from the top-left pixel: what every tracer renders.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace twinray {

// The largest image twinray renders or reads, refused before anything is allocated: 8192 x 8192
// pixels, whose float RGB buffer alone is 768 MiB (the 8-bit copy for a PNG adds 192 MiB). A side may
// be up to 16384 (the scene format's limit), but 16384 x 16384 would need 3 GiB for the buffer.
constexpr std::int64_t max_image_pixels = std::int64_t{8192} * 8192;

struct Rgb {
    float r = 0, g = 0, b = 0;
    friend bool operator==(const Rgb&, const Rgb&) = default;
};

class Image {
public:
    Image(int width, int height)
        : width_(width), height_(height), pixels_(static_cast<std::size_t>(width) * static_cast<std::size_t>(height)) {}

    int width() const { return width_; }
    int height() const { return height_; }
    Rgb& at(int x, int y) { return pixels_[index(x, y)]; }
    const Rgb& at(int x, int y) const { return pixels_[index(x, y)]; }
    const std::vector<Rgb>& pixels() const { return pixels_; }

    friend bool operator==(const Image&, const Image&) = default;

private:
    std::size_t index(int x, int y) const {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x);
    }

    int width_;
    int height_;
    std::vector<Rgb> pixels_;
};

}  // namespace twinray
