// Diagnostic pictures of a surface frame, the figures of Wu et al.: density evaluations per ray
// (their Fig. 5), the particle classification (Fig. 6) and the tile resolutions (Fig. 7).
#pragma once

#include <cstdint>
#include <vector>

#include "render/surface_frame.h"

namespace aquaform {

/// Heat map of the density evaluations each ray spent, over the dimmed image; full scale at
/// `max_evals` (interpolated pixels show as no ray).
Image evals_view(const SurfaceFrame& frame, float max_evals);
/// Heat map of the march steps each ray took (Wu et al. Fig. 5: density evaluations of the
/// stepping, no bisection), over the dimmed image; full scale at `max_steps`.
Image steps_view(const SurfaceFrame& frame, const std::vector<uint32_t>& march_steps, float max_steps);

/// The image with the particle in front at each pixel tinted: splashes yellow, aggregates green.
/// `front_classes`: per pixel 0 (none), 1 (splash), 2 (aggregate).
Image classification_view(const Image& image, const std::vector<uint32_t>& front_classes);

/// The image with each 16 x 16 tile tinted by its ray resolution: full red, half yellow,
/// quarter green, no rays untouched; tile borders drawn.
Image tile_view(const Image& image, const std::vector<uint32_t>& tile_levels, uint32_t tiles_per_row);

}  // namespace aquaform
