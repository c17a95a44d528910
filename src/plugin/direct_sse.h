// twinray's SSE tracer judged directly, without the ABI: the other half of the proof that the ABI carries what the
// judges need (its plug-in, peers/sse_tracer.cpp, must get the same verdicts). `twinray conform sse`.
#pragma once

#include "plugin/judged_tracer.h"

namespace twinray::plugin {

// The exact kernels, --accel auto. Throws std::runtime_error on a CPU without SSE4.1.
class DirectSse final : public JudgedTracer {
public:
    DirectSse();
    std::string description() const override;
    double unit_roundoff() const override { return 0x1p-24; }
    // None: the tracer intersects every kind a scene holds, CSG included.
    std::vector<std::string> missing_kinds(const scene::Scene&) const override { return {}; }
    std::unique_ptr<JudgedScene> build(const scene::Scene& scene) const override;
};

}  // namespace twinray::plugin
