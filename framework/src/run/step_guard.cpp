#include "run/step_guard.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "suffuse/error.hpp"

namespace suffuse::detail {

namespace {

struct SuspectInputs {
  const double *velocity, *stress, *pressure, *porosity, *darcy;  // the last three: null in dry runs
  double max_speed2, courant_limit2;
};

// The fast path: how many points may fail, in passes of integer counts that
// vectorise on AVX2 (a sum of the values, as before, was one long chain of
// dependent additions: floating-point sums are not reordered). A NaN fails
// every `<=`.
template <int D>
[[gnu::always_inline]] inline std::size_t count_suspects(const SuspectInputs& in, std::size_t b, std::size_t e) {
  constexpr double largest = std::numeric_limits<double>::max();
  const double *v = in.velocity, *s = in.stress, *p = in.pressure, *n = in.porosity, *q = in.darcy;
  std::size_t count = 0;
  for (std::size_t i = b; i < e; ++i) {
    double speed2 = 0;
    for (int a = 0; a < D; ++a) speed2 += v[i * D + a] * v[i * D + a];
    count += !(speed2 <= in.max_speed2);
  }
  for (std::size_t i = 6 * b; i < 6 * e; ++i) count += !(std::abs(s[i]) <= largest);
  if (p)
    for (std::size_t i = b; i < e; ++i) count += !(std::abs(p[i]) <= largest);
  if (n)
    for (std::size_t i = b; i < e; ++i) {
      double q2 = 0;
      for (int a = 0; a < D; ++a) q2 += q[i * D + a] * q[i * D + a];
      count += (n[i] != 0 && !(n[i] > 0 && n[i] < 1)) + (n[i] > 0 && !(q2 <= in.courant_limit2 * n[i] * n[i]));
    }
  return count;
}

}  // namespace

void StepGuard::check(Domain& d, std::size_t step, double time, double dt, double transport_dt) const {
  const int D = d.dim();
  const PointSet& pts = d.points;
  const double* v = pts.data(pts.core().velocity);
  const double* s = pts.data(pts.core().stress);
  const double* n = mixture_ ? pts.data(mixture_->porosity) : nullptr;
  const double* p = mixture_ ? pts.data(mixture_->pore_pressure) : nullptr;
  const double* q = mixture_ ? pts.data(mixture_->darcy_flux) : nullptr;
  const double courant_limit = 0.5 * d.grid.min_cell_size() / transport_dt;  // |q| / n below it
  const double max_speed = d.grid.min_cell_size() / dt;  // a cell per step
  // The first failure of a point, if any, by the order of the checks.
  auto failure_of = [&](std::size_t i) -> std::optional<Failure> {
    double speed2 = 0;
    for (int a = 0; a < D; ++a) speed2 += v[i * D + a] * v[i * D + a];
    if (!(speed2 <= max_speed * max_speed))
      return Failure{0, i, "velocity", std::sqrt(speed2),
                     std::isfinite(speed2) ? "moves more than a cell in one step" : "not finite"};
    for (int c = 0; c < 6; ++c)
      if (!std::isfinite(s[i * 6 + c])) return Failure{1, i, "stress", s[i * 6 + c], "not finite"};
    if (p && !std::isfinite(p[i])) return Failure{2, i, "pore_pressure", p[i], "not finite"};
    if (n && n[i] != 0 && !(n[i] > 0 && n[i] < 1))
      return Failure{3, i, "porosity", n[i], std::isfinite(n[i]) ? "outside (0, 1)" : "not finite"};
    if (q && n[i] > 0) {
      double q2 = 0;
      for (int a = 0; a < D; ++a) q2 += q[i * D + a] * q[i * D + a];
      if (!(q2 <= courant_limit * courant_limit * n[i] * n[i]))
        return Failure{4, i, "darcy_flux", std::sqrt(q2),
                       "the pore liquid crosses more than half a cell in one step (q dt / (n h) > 0.5)"};
    }
    return std::nullopt;
  };
  auto before = [](const std::optional<Failure>& a, const std::optional<Failure>& b) {  // a comes first
    return a && (!b || a->check < b->check || (a->check == b->check && a->point < b->point));
  };
  // Only a chunk with suspects is searched point by point.
  auto first_failure = [&](std::size_t b, std::size_t e) {
    std::optional<Failure> first;
    for (std::size_t i = b; i < e; ++i)
      if (auto f = failure_of(i); before(f, first)) first = f;
    return first;
  };
  std::vector<std::optional<Failure>>& found = found_;  // per thread; sized once, no allocation per step
  found.assign(static_cast<std::size_t>(d.exec.threads()), std::nullopt);
  const SuspectInputs in{v, s, p, n, q, max_speed * max_speed, courant_limit * courant_limit};
  d.exec.for_chunks(pts.size(), [&](int t, std::size_t b, std::size_t e) {
    std::size_t suspects = 0;
    d.exec.vector_kernel(D, [&]<int Dim, int>() { suspects = count_suspects<Dim>(in, b, e); });
    if (!suspects) return;
    if (auto f = first_failure(b, e); before(f, found[t])) found[t] = f;
  });
  std::optional<Failure> first;
  for (const auto& f : found)
    if (before(f, first)) first = f;
  if (first) {
    const Failure* f = &*first;
    std::ostringstream msg;
    msg.precision(6);
    const double* x = pts.data(pts.core().position);
    std::string body = "?", material = "?";
    for (const BodyPoints& b : d.bodies)
      if (f->point >= b.range.begin && f->point < b.range.end) {
        body = b.name;
        material = scene_.materials[b.material].name + "' (" + scene_.materials[b.material].phase.type + ")";
      }
    msg << "the run blew up at step " << step << " (t = " << time << " s): " << d.point_name(f->point) << " of body '" << body << "' at (";
    for (int a = 0; a < D; ++a) msg << (a ? ", " : "") << x[f->point * D + a];
    msg << "), material '" << material << ": " << f->field << " = ";
    if (std::isnan(f->value)) msg << "NaN";  // not "-nan": a NaN's sign means nothing
    else msg << f->value;
    msg << ", " << f->problem
        << ". The time step (" << dt << " s) may be too large for this scene: remove /time/dt or lower it "
        << "(or lower /time/cfl), and check loads, gravity and material parameters";
    throw Error(msg.str());
  }
}

}  // namespace suffuse::detail
