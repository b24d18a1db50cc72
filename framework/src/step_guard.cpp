#include "step_guard.hpp"

#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "suffuse/error.hpp"

namespace suffuse::detail {

namespace {

struct Failure {
  std::size_t point;
  const char* field;
  double value;
  const char* problem;
};

}  // namespace

void StepGuard::check(Domain& d, std::size_t step, double time, double dt) const {
  const int D = d.dim();
  const PointSet& pts = d.points;
  const double* v = pts.data(pts.core().velocity);
  const double* s = pts.data(pts.core().stress);
  const double* n = porosity_ ? pts.data(*porosity_) : nullptr;
  const double* p = pore_pressure_ ? pts.data(*pore_pressure_) : nullptr;
  const double max_speed = d.grid.min_cell_size() / dt;  // a cell per step
  std::vector<std::optional<Failure>> found(static_cast<std::size_t>(d.exec.threads()));
  d.exec.for_chunks(pts.size(), [&](int t, std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e && !found[t]; ++i) {
      double speed2 = 0;
      for (int a = 0; a < D; ++a) speed2 += v[i * D + a] * v[i * D + a];
      // Written so that NaN fails every test.
      if (!(speed2 <= max_speed * max_speed)) {
        found[t] = Failure{i, "velocity", std::sqrt(speed2),
                           std::isfinite(speed2) ? "moves more than a cell in one step" : "not finite"};
        break;
      }
      for (int c = 0; c < 6; ++c)
        if (!std::isfinite(s[i * 6 + c])) found[t] = Failure{i, "stress", s[i * 6 + c], "not finite"};
      if (p && !std::isfinite(p[i])) found[t] = Failure{i, "pore_pressure", p[i], "not finite"};
      if (n && n[i] != 0 && !(n[i] > 0 && n[i] < 1)) found[t] = Failure{i, "porosity", n[i], "outside (0, 1)"};
    }
  });
  for (const auto& f : found) {
    if (!f) continue;
    std::ostringstream msg;
    msg.precision(6);
    const double* x = pts.data(pts.core().position);
    std::string body = "?", material = "?";
    for (const BodyPoints& b : d.bodies)
      if (f->point >= b.range.begin && f->point < b.range.end) {
        body = b.name;
        material = scene_.materials[b.material].name + "' (" + scene_.materials[b.material].phase.type + ")";
      }
    msg << "the run blew up at step " << step << " (t = " << time << " s): material point " << f->point
        << " of body '" << body << "' at (";
    for (int a = 0; a < D; ++a) msg << (a ? ", " : "") << x[f->point * D + a];
    msg << "), material '" << material << ": " << f->field << " = " << f->value << ", " << f->problem
        << ". The time step (" << dt << " s) may be too large for this scene: remove /time/dt or lower it "
        << "(or lower /time/cfl), and check loads, gravity and material parameters";
    throw Error(msg.str());
  }
}

}  // namespace suffuse::detail
