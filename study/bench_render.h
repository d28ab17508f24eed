// `aquaform bench render`'s configurations and targets: the reference, uniform (Xiao et al.),
// adaptive (Wu et al.) and each adaptive mechanism alone on one dam-break frame, and the verdicts
// on the adaptive method's targets (the command renders, prints and writes bench_render.json).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/result.h"
#include "gpu/context.h"
#include "render/image_metrics.h"
#include "render/surface_settings.h"
#include "study/render_measure.h"

namespace aquaform::study {

/// One configuration: a method, and for the adaptive method which mechanisms are on.
struct BenchConfig {
    const char* label;
    SurfaceMethod method;
    bool mask, skip, adaptive_res, blend;
    const char* what;
};

/// Every configuration, in the table's order (the reference is rendered first and always: every
/// metric is against it), and the ones --quick renders.
const std::vector<BenchConfig>& bench_configs();
const std::vector<std::string>& quick_bench_configs();
const BenchConfig* find_config(const std::string& label);
/// "reference, uniform, adaptive, ...": what --configs accepts.
std::string known_labels();
/// --configs a,b,c in the table's order; the reference is always rendered.
Result<std::vector<const BenchConfig*>> parse_configs(const std::string& text);
/// `base` with the configuration's method and mechanisms, as that method's registry settings.
MethodSettings settings_for(const BenchConfig& c, SurfaceSettings base);
/// `base` drawn by the exhaustive reference.
MethodSettings reference_settings(SurfaceSettings base);

struct Measured {
    const BenchConfig* config;
    RenderMeasurement m;  ///< with the settings rendered
    SurfaceComparison cmp;
};

/// One target's verdict for the terminal and the JSON.
struct Verdict {
    nlohmann::json json;
    std::string line;
};

/// Mask + skip evaluations per ray against uniform's (target <= 40 % at equal or lower depth error).
Verdict evals_target(const std::vector<Measured>& results);
/// Adaptive resolution: march + upsample against the full-resolution march, PSNR against it.
Verdict resolution_target(const std::vector<Measured>& results);
/// Real time on a GPU: the adaptive reconstruction of 1M particles at 1920x1080 within 10 ms.
/// `requested`: --particles (the lattice holds a little fewer: 986,078 for 1,000,000).
Verdict gpu_target(const std::vector<Measured>& results, const gpu::DeviceInfo& device, long requested, uint32_t particles,
                   uint32_t width, uint32_t height);

}  // namespace aquaform::study
