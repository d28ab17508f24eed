// Experimental surge-front data for the dam break, to measure a run against.
//
// Martin & Moyce (1952), "An experimental study of the collapse of liquid columns on a rigid
// horizontal plane", Phil. Trans. R. Soc. A 244: a column of width a and height 2a (n^2 = 2),
// front position Z = x / a against time T = t sqrt(2 g / a). Values as tabulated in their
// Tables 2 and 6 (they agree with the points digitised from their Fig. 3 for a = 2.25 in).
#pragma once

#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace aquaform {

struct FrontSample {
    double T;  ///< t sqrt(2 g / a)
    double Z;  ///< front / a
};

std::span<const FrontSample> martin_moyce_front();

/// A run's front in the experiment's units.
std::vector<FrontSample> nondimensional_front(std::span<const std::pair<double, double>> time_front, double a,
                                              double g);

struct FrontComparison {
    int points = 0;              ///< experimental points within the run's time span
    double mean_relative = 0.0;  ///< mean |Z_sim - Z_exp| / Z_exp
    double max_relative = 0.0;
};

/// Compares a run (linear interpolation in T) with every experimental point it spans whose T
/// lies in [T_min, T_max] (runs of different lengths are compared over one range so that their
/// errors mean the same thing); empty when it spans none.
std::optional<FrontComparison> compare_with_martin_moyce(std::span<const FrontSample> run, double T_min = 0.0,
                                                         double T_max = 1.0e30);

}  // namespace aquaform
