#include "quasi_static/strength_reduction.hpp"

#include <algorithm>
#include <cmath>

#include "suffuse/tensor.hpp"

namespace suffuse::detail {

StrengthReduction::StrengthReduction(const FactorOfSafetySpec& controls, Domain& domain, const Materials& materials,
                                     QuasiStatic& solver, std::optional<FieldId> mechanism)
    : controls_(controls), d_(domain), materials_(materials), solver_(solver), mechanism_(mechanism) {}

void StrengthReduction::save_points() {
  PointSet& pts = d_.points;
  saved_.resize(pts.field_count());
  for (FieldId f = 0; f < pts.field_count(); ++f) {
    const auto v = pts.values(f);
    saved_[f].assign(v.begin(), v.end());
  }
}

void StrengthReduction::restore_points() {
  PointSet& pts = d_.points;
  for (FieldId f = 0; f < pts.field_count(); ++f) std::copy(saved_[f].begin(), saved_[f].end(), pts.data(f));
}

bool StrengthReduction::holds(double F, double time, double dt, SafetyFactor& result) {
  solver_.reduce_strength(F, controls_.max_iterations);
  const std::optional<int> iterations = solver_.solve(time - dt, dt);  // the loads at `time`
  if (result.solves++ == 0 && !solver_.residuals().empty()) result.start_residual = solver_.residuals().front();
  result.newton_iterations += iterations ? *iterations : solver_.attempted_iterations();
  if (!iterations) return false;
  // The solution's strain increment, sym(L) dt at the points (L of its last evaluation).
  const PointSet& pts = d_.points;
  const int dim = d_.dim();
  const double* L = pts.data(pts.core().velocity_gradient);
  for (std::size_t p = 0; p < pts.size(); ++p)
    for (int i = 0; i < dim; ++i)
      for (int j = i; j < dim; ++j)
        strain_[p * 6 + tensor::voigt_index(i, j)] +=
            0.5 * (L[p * dim * dim + i * dim + j] + L[p * dim * dim + j * dim + i]) * dt;
  return true;
}

SafetyFactor StrengthReduction::evaluate(double time, double dt) {
  SafetyFactor result;
  save_points();
  // Whatever a solve throws (a phase's error, PETSc's), the run is left as
  // it was found: its strengths, its pressure unknowns, its points.
  struct PutBack {
    StrengthReduction& reduction;
    bool armed = true;
    ~PutBack() {
      if (!armed) return;
      reduction.solver_.reduce_strength(std::nullopt);
      reduction.restore_points();
    }
  } put_back{*this};
  PointSet& pts = d_.points;
  // No erosion in the solves: the factor is the last equilibrium's. The
  // step's eigenstrain increment is not imposed again, and the fines the
  // step's transport has just eroded, whose void ratio and strain the next
  // step applies, are not applied here (a phase that applies them in its
  // stress update: phase/suffosion).
  if (const auto e = materials_.eigenstrain_increment_field()) std::fill_n(pts.data(*e), pts.size() * 6, 0.0);
  if (const auto df = pts.find(coupling::eroded_fraction_increment)) std::fill_n(pts.data(*df), pts.size(), 0.0);
  strain_.assign(pts.size() * 6, 0.0);
  double lo = 1, hi = std::numeric_limits<double>::infinity();
  if (!holds(1.0, time, dt, result)) {
    // Not even the full strength holds (the run's own step would fail):
    // factors below 1, each from the state as it was.
    hi = 1;
    for (lo = 1 / (1 + controls_.increment);; lo /= 1 + controls_.increment) {
      restore_points();
      std::fill(strain_.begin(), strain_.end(), 0.0);
      if (lo < 1 / controls_.max_factor) {
        lo = 0;  // no equilibrium at any strength the controls try
        break;
      }
      if (holds(lo, time, dt, result)) break;
      hi = lo;
    }
  }
  if (lo > 0) {
    while (hi - lo > controls_.tolerance && lo < controls_.max_factor) {
      const double F = std::isfinite(hi) ? 0.5 * (lo + hi) : std::min(lo + controls_.increment, controls_.max_factor);
      if (holds(F, time, dt, result))
        lo = F;
      else
        hi = F;
    }
  }
  put_back.armed = false;
  solver_.reduce_strength(std::nullopt);
  result.factor = lo;
  result.failed_at = hi;
  restore_points();
  if (mechanism_) {
    double* out = pts.data(*mechanism_);
    for (std::size_t p = 0; p < pts.size(); ++p) {
      const double* e = &strain_[p * 6];
      const double mean = (e[0] + e[1] + e[2]) / 3;
      double e2 = 0;
      for (int c = 0; c < 6; ++c) {
        const double dev = c < 3 ? e[c] - mean : e[c];
        e2 += (c < 3 ? 1.0 : 2.0) * dev * dev;
      }
      out[p] = std::sqrt(2.0 / 3.0 * e2);  // the equivalent shear strain, sqrt(2/3 e:e)
    }
  }
  return result;
}

}  // namespace suffuse::detail
