#include "sse/cpu.h"

#include <cstdlib>
#include <cstring>

namespace twinray::sse {

bool cpu_supports_sse41() {
    const char* simulate = std::getenv("TWINRAY_SIMULATE_NO_SSE41");
    if (simulate != nullptr && std::strcmp(simulate, "1") == 0) {
        return false;
    }
    __builtin_cpu_init();
    return __builtin_cpu_supports("sse4.1");
}

std::string missing_sse41_message() {
    return "this CPU does not support SSE4.1, which the optimized tracer needs; "
           "use --tracer reference (or reference-float) instead";
}

}  // namespace twinray::sse
