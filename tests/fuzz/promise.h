// How a fuzz target reports a broken promise: abort, so libFuzzer keeps the input as a crash.
#pragma once

#include <cstdio>
#include <cstdlib>

namespace twinray::fuzz {

inline void expect(bool holds, const char* target, const char* promise) {
    if (!holds) {
        std::fprintf(stderr, "%s: broken promise: %s\n", target, promise);
        std::abort();
    }
}

}  // namespace twinray::fuzz
