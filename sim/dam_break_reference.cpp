#include "sim/dam_break_reference.h"

#include <algorithm>
#include <cmath>

namespace aquaform {

namespace {

constexpr FrontSample kMartinMoyce[] = {
    {0.41, 1.11}, {0.84, 1.22}, {1.19, 1.44}, {1.43, 1.67}, {1.63, 1.89}, {1.83, 2.11}, {1.98, 2.33}, {2.20, 2.56},
    {2.32, 2.78}, {2.51, 3.00}, {2.65, 3.22}, {2.83, 3.44}, {2.98, 3.67}, {3.11, 3.89}, {3.33, 4.11},
};

}  // namespace

std::span<const FrontSample> martin_moyce_front() { return kMartinMoyce; }

std::vector<FrontSample> nondimensional_front(std::span<const std::pair<double, double>> time_front, double a,
                                              double g) {
    std::vector<FrontSample> out;
    const double time_scale = std::sqrt(2.0 * g / a);
    for (const auto& [t, x] : time_front) out.push_back({t * time_scale, x / a});
    return out;
}

std::optional<FrontComparison> compare_with_martin_moyce(std::span<const FrontSample> run, double T_min, double T_max) {
    FrontComparison c;
    double sum = 0.0;
    for (const FrontSample& e : kMartinMoyce) {
        if (e.T < T_min || e.T > T_max) continue;
        auto after = std::find_if(run.begin(), run.end(), [&](const FrontSample& s) { return s.T >= e.T; });
        if (after == run.begin() || after == run.end()) continue;
        const FrontSample& b = *(after - 1);
        const double z = b.Z + (after->Z - b.Z) * (e.T - b.T) / (after->T - b.T);
        const double rel = std::abs(z - e.Z) / e.Z;
        sum += rel;
        c.max_relative = std::max(c.max_relative, rel);
        ++c.points;
    }
    if (c.points == 0) return std::nullopt;
    c.mean_relative = sum / c.points;
    return c;
}

}  // namespace aquaform
