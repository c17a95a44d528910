// Shared by the extremes tests (label extremes): the tracers they run, by name, skipped where the CPU
// lacks SSE4.1, and each one's unit roundoff.
#pragma once

#include "numerics/numerics.h"
#include "sse/cpu.h"

#include <gtest/gtest.h>

#include <limits>
#include <string>

namespace twinray::test {

// u = ε/2 of the tracer's precision.
inline double unit_roundoff(numerics::TracerKind kind) {
    return kind == numerics::TracerKind::reference_double ? std::numeric_limits<double>::epsilon() / 2
                                                          : std::numeric_limits<float>::epsilon() / 2;
}

class EachTracer : public ::testing::TestWithParam<numerics::TracerKind> {
protected:
    void SetUp() override {
        if (GetParam() == numerics::TracerKind::sse && !sse::cpu_supports_sse41()) {
            GTEST_SKIP() << "this CPU lacks SSE4.1";
        }
    }
};

inline std::string tracer_test_name(const ::testing::TestParamInfo<numerics::TracerKind>& info) {
    switch (info.param) {
        case numerics::TracerKind::reference_double: return "Reference";
        case numerics::TracerKind::reference_float: return "ReferenceFloat";
        case numerics::TracerKind::sse: return "Sse";
    }
    return "Unknown";
}

}  // namespace twinray::test

#define TWINRAY_FOR_EACH_TRACER(Suite)                                                                         \
    INSTANTIATE_TEST_SUITE_P(                                                                                  \
        Tracers, Suite,                                                                                        \
        ::testing::Values(twinray::numerics::TracerKind::reference_double,                                     \
                          twinray::numerics::TracerKind::reference_float, twinray::numerics::TracerKind::sse), \
        twinray::test::tracer_test_name)
