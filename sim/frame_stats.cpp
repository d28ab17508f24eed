#include "sim/frame_stats.h"

#include <algorithm>

namespace aquaform {

FrameStats reduce_stats(std::span<const shader::StatsPartial> partials, uint32_t particles,
                        std::optional<float> front_wall_x) {
    FrameStats s;
    s.particles = particles;
    double sum_err = 0.0, sum_dev = 0.0, outside = 0.0, non_finite = 0.0;
    double front = -1.0e30;
    for (const auto& p : partials) {
        sum_err += p.sum_density_error;
        sum_dev += p.sum_abs_density_dev;
        s.max_density_error = std::max<double>(s.max_density_error, p.max_density_error);
        s.kinetic_energy += p.sum_kinetic_energy;
        s.max_speed = std::max<double>(s.max_speed, p.max_speed);
        outside += p.outside;
        non_finite += p.non_finite;
        front = std::max<double>(front, p.front);
    }
    if (particles) {
        s.mean_density_error = sum_err / particles;
        s.mean_density_deviation = sum_dev / particles;
    }
    s.outside = static_cast<uint32_t>(outside + 0.5);
    s.non_finite = static_cast<uint32_t>(non_finite + 0.5);
    if (front_wall_x && front > -1.0e29) s.front = front - *front_wall_x;
    return s;
}

}  // namespace aquaform
