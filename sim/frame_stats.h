// Per-frame figures of a simulation (one row of stats.csv).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>

#include <glm/glm.hpp>

#include "shaders/shared/sim/pbf_layout.h"

namespace aquaform {

/// A frame's whitewater figures (sim/whitewater.h; stats.csv).
struct WhitewaterCounts {
    uint32_t spray = 0, foam = 0, bubbles = 0;  ///< alive at the frame's end, by kind
    uint64_t emitted = 0;                       ///< made during the frame
    uint64_t dropped = 0;                       ///< made or carried but not kept: the pool was full
    uint32_t live() const { return spray + foam + bubbles; }
};

/// The water that came and went (sim/fluid_flow.h): particle totals since the start.
struct FlowCounts {
    uint64_t emitted = 0;      ///< made by the nozzles
    uint64_t removed = 0;      ///< taken by the sinks (those marked at this frame's end included)
    uint64_t not_emitted = 0;  ///< of layers that found the capacity full (or the ids used up)
};

struct FrameStats {
    double time_s = 0.0;              ///< simulated time at the end of the frame
    double mean_density_error = 0.0;  ///< mean of max(rho/rho0 - 1, 0): compression, the constraint error
    double max_density_error = 0.0;
    double mean_density_deviation = 0.0;  ///< mean |rho/rho0 - 1|, free-surface deficiency included
    double kinetic_energy = 0.0;          ///< [J]
    double max_speed = 0.0;               ///< [m/s]
    uint32_t substeps = 0;                ///< solver steps this frame took (the time-step rule)
    double dt = 0.0;                      ///< their step [s]
    double cfl_number = 0.0;              ///< max_speed * dt / h at the frame's end (the rule keeps it <= cfl)
    bool speed_capped = false;            ///< the scene's safety cap (solver.max_speed) bound in this frame
    uint32_t particles = 0;               ///< alive at the frame's end (those a sink took then not counted)
    uint32_t outside = 0;                 ///< particles outside the domain box (leaked)
    uint32_t in_solid = 0;                ///< particles whose centre is inside a solid (collision failed)
    uint32_t non_finite = 0;              ///< particles with NaN or infinite state
    std::optional<double> front;          ///< dam-break front [m from the wall], when the scene has one
    double splash_fraction = 0.0;         ///< fraction of the particles with few neighbours (kSplashNeighborFraction)
    /// Dam breaks: the highest fluid point on the far wall (domain.max.x), the top of the highest
    /// particle within a spacing of it that is not spray (kSplashNeighborFraction: the sheet
    /// climbing the wall, not droplets flying up it), above the floor [m]; empty when none.
    std::optional<double> runup;
    /// Connected groups smaller than droplet_size_limit() (PbfSolver::set_measure_droplets).
    std::optional<uint32_t> droplets;
    /// Fraction of the particles with more neighbours than their list holds: they, and on SIMD
    /// hardware the particles sharing their instructions, scan 27 cells instead (a slow step).
    double list_overflow_fraction = 0.0;
    std::map<std::string, double> gpu_ms;        ///< GPU time per pass during this frame
    std::optional<WhitewaterCounts> whitewater;  ///< with the scene's whitewater on
    std::optional<FlowCounts> flow;              ///< with the scene's emitters or sinks
};

/// A splash particle has fewer fluid neighbours within h than this fraction of a full interior
/// neighbourhood. A flat free surface keeps about half, a block's edge a quarter; below a
/// quarter a particle is in spray, a droplet or a filament, not in the bulk or on its surface.
/// Walls do not count: a droplet running down a wall is still spray. (A corner where three
/// faces of a block meet keeps an eighth: a scene starts with a few such particles.)
inline constexpr double kSplashNeighborFraction = 0.25;

/// Neighbours within h of an interior particle at rest density: the (4 pi / 3) (h / s)^3
/// particle volumes of the sphere, less the particle itself (32.5 for h = 2 s).
double full_neighbor_count(float kernel_radius_factor);

/// Finishes the GPU's per-workgroup reduction. `front_wall_x` turns the front's x into a
/// distance from the wall; a front below -1e29 (no particle on the floor) stays empty; so does
/// a runup below -1e29 (no particle at the wall), else `runup_offset` is added (the particle's
/// radius, less the floor's height).
FrameStats reduce_stats(std::span<const shader::StatsPartial> partials, uint32_t particles,
                        std::optional<float> front_wall_x, float runup_offset = 0.0f);

/// Groups that hold fewer particles than this are droplets: 1 % of the particles, so a droplet
/// is the same fraction of the fluid's volume at every particle count (a lone particle always is one).
uint32_t droplet_size_limit(uint32_t particles);

/// Droplets: connected groups of particles, two particles being connected when closer than
/// `link` (the solver uses h: particles farther apart exert no force on each other, so such a
/// group moves as a body of its own), with fewer than `size_limit` members. Non-finite
/// positions belong to no group. O(N): a counting sort into cells of at least `link`, then
/// union-find over the 27 cells around each particle.
uint32_t count_droplets(std::span<const glm::vec4> positions, float link, uint32_t size_limit);

}  // namespace aquaform
