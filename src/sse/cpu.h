// Whether this CPU can run the SSE tracer. Compiled without -msse4.1, so asking never itself executes
// an SSE4.1 instruction.
#pragma once

#include <string>

namespace twinray::sse {

// True when the CPU reports SSE4.1. Setting the environment variable TWINRAY_SIMULATE_NO_SSE41 to 1
// makes it answer false, so the refusal path can be tested on any machine.
bool cpu_supports_sse41();

// What a user is told when the SSE tracer cannot run here.
std::string missing_sse41_message();

}  // namespace twinray::sse
