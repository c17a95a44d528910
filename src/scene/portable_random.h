// Seeded random numbers that are the same on every platform and standard library (the standard
// distributions are not portable): splitmix64 (Steele, Lea, Flood 2014), doubles made by hand from
// the top 53 bits. For generated scenes, tests and benchmarks.
#pragma once

#include <cstdint>

namespace twinray {

class SplitMix64 {
public:
    explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
    std::uint64_t next() {
        std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        return z ^ (z >> 31);
    }
    // Uniform in [low, high).
    double uniform(double low, double high) {
        return low + (high - low) * static_cast<double>(next() >> 11) * 0x1.0p-53;
    }

private:
    std::uint64_t state_;
};

}  // namespace twinray
