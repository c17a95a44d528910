// libFuzzer target: the BVHs change no answer. The bytes become a small scene (up to 300 primitives:
// spheres, boxes, capped cylinders, planes and CSG trees of them, opaque, mirror and transparent, at
// coordinates from small integers, where they coincide and overlap, to 1e±300) and up to 16 rays, most aimed
// at a primitive (bvh_differential.h). Every tracer then answers with and without its BVH: the SSE tracer
// (exact or fast kernels), reference<double> and reference<float>, per ray (hit, leaf, t, normal, point, the
// colour of the whole ray tree) and for a small image. Any bit that differs aborts with what differed, so
// libFuzzer keeps the input. Built only with -DTWINRAY_FUZZ=ON (preset `fuzz`, clang); docs/reliability.md.
#include "bvh_differential.h"

#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    twinray::fuzz::DifferentialCase input = twinray::fuzz::CaseDecoder(data, size).decode();
    std::string difference = twinray::fuzz::first_difference(input);
    if (!difference.empty()) {
        std::fprintf(stderr, "bvh_differential_fuzz: %s\nscene: %s\n", difference.c_str(), input.scene_text.c_str());
        std::abort();
    }
    return 0;
}
