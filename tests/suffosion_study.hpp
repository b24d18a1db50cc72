// The DEM study's relations for phase/suffosion (seed 001; docs/suffosion.md)
// with its fitted values, written out independently of the plugin: the
// tests' yardstick.
#pragma once

#include <cmath>

namespace suffuse::test::suffosion_study {

inline constexpr double M_so = 0.71, f_so0 = 0.02, M_c = 0.86, A = 0.85, xi = 8, beta = 1.5;
// The onset: the eroded fraction at which erosion starts to strain the sample.
inline double onset(double eta) { return eta < M_so ? f_so0 * std::sqrt(1 - eta * eta / (M_so * M_so)) : 0.0; }
// d eps_v / d f_er past the onset.
inline double compaction_rate(double eta) { return A * (1 - std::pow(eta / M_c, xi)); }
// d eps_v / d eps_s.
inline double dilatancy(double eta) { return (M_c * M_c - eta * eta) / (beta * eta); }

}  // namespace suffuse::test::suffosion_study
