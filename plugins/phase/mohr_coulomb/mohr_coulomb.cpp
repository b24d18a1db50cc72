// phase/mohr_coulomb: elastic-perfectly plastic Mohr-Coulomb skeleton with a
// non-associated flow rule (dilatancy angle) and an optional tension cut-off,
// integrated with the exact return mapping in principal stresses of Clausen,
// Damkilde & Andersen (2006, 2007): return to the yield plane, to one of its
// two edges (triaxial compression and extension meridians) or to the apex.
// Elasticity is isotropic with the Jaumann rate, as phase/linear_elastic.
//
// Signs: the core's, tension positive. Principal stresses are sorted
// s1 >= s2 >= s3 (s1 the least compressive). The yield function is
//   f = (s1 - s3) + (s1 + s3) sin(phi) - 2 c cos(phi) <= 0
// and the plastic potential g the same with psi for phi. The apex, where
// every edge meets, is the isotropic tension c cot(phi). With a tension
// cut-off s_i <= t the return is an active set of the cone's planes and the
// cut-off's (with_cut_off; mohr_coulomb_return.hpp). With
// state_friction_slope the friction follows the void ratio through the
// state parameter (state_friction.hpp), each point's from its state at the
// step's start. A strength reduction divides c, tan(phi), tan(psi) and t.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <suffuse/plugin.hpp>
#include <suffuse/tensor.hpp>

#include "mohr_coulomb_return.hpp"
#include "state_friction.hpp"

namespace {

using suffuse_mohr_coulomb::MohrCoulombReturn;
using suffuse_mohr_coulomb::Vec3;

constexpr double degree = 3.14159265358979323846 / 180;

class MohrCoulomb final : public suffuse::Phase {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("density").with_unit("kg/m^3").above(0).doc("Mass density (of the grains in a saturated body)");
    s.number("youngs_modulus").with_unit("Pa").above(0).doc("Young's modulus E");
    s.number("poisson_ratio").with_unit("-").above(-1).below(0.5).fallback(0.3).doc("Poisson's ratio nu");
    s.number("friction_angle").with_unit("deg").at_least(0).below(90).doc("Friction angle phi");
    s.number("cohesion").with_unit("Pa").at_least(0).fallback(0.0).doc("Cohesion c");
    s.number("dilatancy_angle").with_unit("deg").at_least(0).below(90).fallback(0.0).doc(
        "Dilatancy angle psi of the plastic potential (psi = phi: associated flow)");
    s.number("tensile_strength").with_unit("Pa").at_least(0).may_be_absent().doc(
        "Tension cut-off: no principal (effective) stress above it. Absent: the apex of the cone, c cot(phi); "
        "required for phi = 0");
    s.number("state_friction_slope").with_unit("-").at_least(0).may_be_absent().doc(
        "k: the friction follows the state parameter psi = e - e_cs(p') (Wood, Belkheir and Liu 1994): the stress "
        "ratio in triaxial compression M(psi) = M_cs (1 - k psi), M_cs that of friction_angle (then the "
        "critical-state friction), kept within 0.1 and 2 M_cs; docs/soil-models.md. Needs initial_void_ratio, "
        "critical_void_ratio and critical_state_slope; absent: a constant friction");
    s.number("initial_void_ratio").with_unit("-").above(0).may_be_absent().doc(
        "e_0 of every point (with state_friction_slope): the void ratio then follows the volume (and, under "
        "phase/suffosion, the fines lost)");
    s.number("critical_void_ratio").with_unit("-").above(0).may_be_absent().doc(
        "e_Gamma: the void ratio on the critical state line at reference_pressure (with state_friction_slope)");
    s.number("critical_state_slope").with_unit("-").at_least(0).may_be_absent().doc(
        "lambda: the critical state line's slope in e - ln p' (with state_friction_slope)");
    s.number("reference_pressure").with_unit("Pa").above(0).fallback(1.0e3).doc(
        "The mean effective stress at which critical_void_ratio is given (with state_friction_slope)");
    return s;
  }

  static std::vector<suffuse::ParameterIssue> check(const suffuse::Parameters& p, int) {
    std::vector<suffuse::ParameterIssue> issues;
    const double phi = p.number("friction_angle"), psi = p.number("dilatancy_angle"), c = p.number("cohesion");
    if (psi > phi)
      issues.push_back({"dilatancy_angle", "dilatancy above friction", "at most friction_angle = " + std::to_string(phi),
                        std::to_string(psi)});
    if (phi == 0 && c == 0)
      issues.push_back({"cohesion", "no strength at all", "cohesion > 0 when friction_angle is 0", "0"});
    if (phi == 0 && !p.has("tensile_strength"))
      issues.push_back({"tensile_strength", "no tension limit", "a tensile_strength when friction_angle is 0 (Tresca)",
                        "nothing"});
    for (const char* key : {"initial_void_ratio", "critical_void_ratio", "critical_state_slope"})
      if (p.has("state_friction_slope") != p.has(key))
        issues.push_back({key, p.has(key) ? "a state parameter without a state friction" : "no state to follow",
                          p.has(key) ? "state_friction_slope too, or no " + std::string(key)
                                     : std::string(key) + " with state_friction_slope",
                          p.has(key) ? "no state_friction_slope" : "nothing"});
    if (p.has("state_friction_slope") && phi == 0)
      issues.push_back({"friction_angle", "no critical-state friction to scale",
                        "friction_angle > 0 with state_friction_slope", "0"});
    if (p.has("tensile_strength") && phi > 0) {
      const double apex = c * std::cos(phi * degree) / std::sin(phi * degree);
      if (p.number("tensile_strength") > apex)
        issues.push_back({"tensile_strength", "cut-off beyond the apex",
                          "at most c cot(phi) = " + std::to_string(apex) + " Pa",
                          std::to_string(p.number("tensile_strength"))});
    }
    return issues;
  }

  explicit MohrCoulomb(const suffuse::PluginArgs& args)
      : rho_(args.params.number("density")),
        nu_(args.params.number("poisson_ratio")),
        E_(args.params.number("youngs_modulus")),
        G_(E_ / (2 * (1 + nu_))),
        lambda_(E_ * nu_ / ((1 + nu_) * (1 - 2 * nu_))),
        cohesion_(args.params.number("cohesion")),
        phi_(args.params.number("friction_angle") * degree),
        psi_(args.params.number("dilatancy_angle") * degree),
        tensile_strength_(args.params.maybe_number("tensile_strength")),
        return_(return_for(1.0, phi_)) {
    if (args.params.has("state_friction_slope"))
      state_ = suffuse_mohr_coulomb::StateFriction{suffuse_mohr_coulomb::StateFriction::ratio_of(phi_),
                                                   args.params.number("state_friction_slope"),
                                                   args.params.number("critical_void_ratio"),
                                                   args.params.number("critical_state_slope"),
                                                   args.params.number("reference_pressure")};
    e0_ = args.params.maybe_number("initial_void_ratio").value_or(0.0);
  }

  double density() const override { return rho_; }
  double p_wave_modulus() const override { return lambda_ + 2 * G_; }

  void add_fields(suffuse::PointSet& points) override {
    using K = suffuse::FieldKind;
    plastic_strain_ =
        points.add_field({"plastic_strain", K::SymmetricTensor, "-", "accumulated plastic strain (Mohr-Coulomb)", true});
    yielding_ = points.add_field({"yielding", K::Scalar, "-", "1 where the last step was plastic, else 0", true});
    trial_stress_ = points.add_field(
        {"mohr_coulomb_trial_stress", K::SymmetricTensor, "Pa", "the elastic trial stress of the last plastic step", false});
    if (!state_) return;
    e_ = points.add_field({"void_ratio", K::Scalar, "-", "void ratio e", true});
    state_parameter_ = points.add_field(
        {"state_parameter", K::Scalar, "-", "psi = e - e_cs(p'): positive looser than critical", true});
    friction_ = points.add_field(
        {"friction_angle", K::Scalar, "deg", "the friction angle of the last step, from the state at its start", true});
  }

  // The state friction's void ratio, state parameter and friction angle.
  void initialise(suffuse::PointSet& points, suffuse::PointRange range) const override {
    if (!state_) return;
    const double* s = points.data(points.core().stress);
    for (std::size_t p = range.begin; p < range.end; ++p) {
      const double mean = suffuse::tensor::mean_stress(s + p * 6);
      points.data(e_)[p] = e0_;
      points.data(state_parameter_)[p] = state_->state_parameter(e0_, mean);
      points.data(friction_)[p] = state_->friction(e0_, mean) / degree;
    }
  }

  // The consistent tangent of the return each point made in its last update
  // (Clausen, Damkilde & Andersen 2007; the spin of the principal axes as in
  // de Souza Neto, Peric & Owen 2008, section A.5): with it the quasi-static
  // Newton iterations converge quadratically where points yield. It is not
  // symmetric for psi < phi; at the apex it is zero (the core then holds the
  // point's nodes by its creep term).
  bool tangent(const suffuse::StressBatch& batch, std::span<double> stiffness) const override {
    const double F = batch.strength_reduction;
    const MohrCoulombReturn reduced = return_for(F, phi_);
    const MohrCoulombReturn& ret = F == 1.0 ? return_ : reduced;
    const suffuse::PointSet& pts = batch.points;
    const double* yielding = pts.data(yielding_);
    const double* trial = pts.data(trial_stress_);
    const double* friction = state_ ? pts.data(friction_) : nullptr;
    for (std::size_t p = batch.range.begin; p < batch.range.end; ++p) {
      double* D = stiffness.data() + (p - batch.range.begin) * 36;
      if (yielding[p] == 0)
        suffuse::tensor::isotropic_stiffness(lambda_ + 2 * G_ / 3, G_, D);
      else if (friction)  // the return of the point's own friction
        plastic_tangent(return_for(F, friction[p] * degree), suffuse::tensor::to_matrix(trial + p * 6), D);
      else
        plastic_tangent(ret, suffuse::tensor::to_matrix(trial + p * 6), D);
    }
    return true;
  }
  bool elastic_stiffness(const suffuse::StressBatch& batch, std::span<double> stiffness) const override {
    for (std::size_t p = batch.range.begin; p < batch.range.end; ++p)
      suffuse::tensor::isotropic_stiffness(lambda_ + 2 * G_ / 3, G_, stiffness.data() + (p - batch.range.begin) * 36);
    return true;
  }
  void update_stress(const suffuse::StressBatch& batch) const override {
    const MohrCoulombReturn reduced = return_for(batch.strength_reduction, phi_);
    const MohrCoulombReturn& ret = batch.strength_reduction == 1.0 ? return_ : reduced;
    if (batch.points.dim() == 2)
      update<2>(batch, ret);
    else
      update<3>(batch, ret);
  }
  bool reduces_strength() const override { return true; }

 private:
  // The return of the strength divided by F (a strength reduction; F = 1:
  // the material's own): c / F, tan(phi) / F and tan(psi) / F (the
  // dilatancy reduced alike, so it stays at most the friction), a tensile
  // strength t / F. The cone's apex, (c / F) / tan(phi_F) = c cot(phi),
  // does not move, so t / F stays below it.
  // `friction`: phi_, or a point's own (state_friction_slope), the dilatancy
  // at most it.
  MohrCoulombReturn return_for(double F, double friction) const {
    const bool own = F == 1.0;  // exactly the given angles (atan(tan(x)) may differ from x in its last bit)
    const double dilatancy = std::min(psi_, friction);
    const double phi = own ? friction : std::atan(std::tan(friction) / F);
    const double psi = own ? dilatancy : std::atan(std::tan(dilatancy) / F);
    const double c = cohesion_ / F;
    double tension = std::numeric_limits<double>::infinity();  // Tresca without a cut-off is refused
    if (tensile_strength_)
      tension = *tensile_strength_ / F;
    else if (phi > 0)
      tension = c * std::cos(phi) / std::sin(phi);
    return MohrCoulombReturn(G_, lambda_, phi, c, psi, tension);
  }

  // The principal stresses of s, sorted s1 >= s2 >= s3, and their axes (column a for s_a).
  struct PrincipalAxes {
    Vec3 values;
    Eigen::Matrix3d axes;
    double tolerance;  // of the return, relative to the stress and the cohesion
  };
  // A plane-strain stress (no out-of-plane shear, as in every 2D run) has
  // the out-of-plane axis as one principal axis and the in-plane pair in
  // closed form: one square root, where Eigen's 3x3 solver takes an atan2, a
  // cos and a sin, and cross products for the axes. That solver was most of
  // the levee's stress stage, at every point and step, yielding or not.
  // The in-plane principal stresses m +- r (centre and radius of Mohr's
  // circle, h the half difference of s_xx and s_yy), if s is such a stress
  // and they and s_zz are finite; anything else (a NaN, an overflow) goes
  // through Eigen's solver, as every stress did before, and stays NaN.
  static bool mohr_circle(const suffuse::tensor::Matrix& s, double& m, double& h, double& r) {
    if (!(s[0][2] == 0 && s[1][2] == 0)) return false;
    m = 0.5 * (s[0][0] + s[1][1]), h = 0.5 * (s[0][0] - s[1][1]);
    r = std::sqrt(h * h + s[0][1] * s[0][1]);
    return std::isfinite(m) && std::isfinite(r) && std::isfinite(s[2][2]);
  }
  // {hi, lo, zz} sorted descending: order[k] is the index of s_k among them.
  static std::array<int, 3> descending(const Vec3& v) {
    std::array<int, 3> order{0, 1, 2};  // v[0] >= v[1] always (hi, lo)
    if (v[2] > v[0])
      order = {2, 0, 1};
    else if (v[2] > v[1])
      order = {0, 2, 1};
    return order;
  }
  static Eigen::Matrix3d to_eigen(const suffuse::tensor::Matrix& s) {
    Eigen::Matrix3d m;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m(i, j) = s[i][j];
    return m;
  }
  double tolerance_of(const Vec3& values) const {
    return 1e-12 * (std::abs(values[0]) + std::abs(values[2]) + cohesion_);
  }
  // The principal stresses alone, sorted: all an elastic step needs.
  Vec3 principal_values(const suffuse::tensor::Matrix& s) const {
    double m, h, r;
    if (!mohr_circle(s, m, h, r)) {
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
      eig.computeDirect(to_eigen(s), Eigen::EigenvaluesOnly);  // the values principal_axes finds
      return {eig.eigenvalues()(2), eig.eigenvalues()(1), eig.eigenvalues()(0)};
    }
    const Vec3 v{m + r, m - r, s[2][2]};
    const auto k = descending(v);
    return {v[k[0]], v[k[1]], v[k[2]]};
  }
  PrincipalAxes principal_axes(const suffuse::tensor::Matrix& s) const {
    PrincipalAxes out;
    double m, h, r;
    if (mohr_circle(s, m, h, r)) {
      const Vec3 v{m + r, m - r, s[2][2]};
      // The major in-plane axis from the better conditioned row of (s - hi I)
      // x = 0 (its larger component is at least r), scaled by that component
      // first so that a tiny shear does not underflow its length.
      const double c = s[0][1];
      double x = h >= 0 ? h + r : c, y = h >= 0 ? c : r - h;
      const double larger = std::max(std::abs(x), std::abs(y));
      if (larger > 0) {
        x /= larger, y /= larger;
        const double length = std::sqrt(x * x + y * y);
        x /= length, y /= length;
      } else {
        x = 1, y = 0;  // isotropic in the plane: any pair of axes
      }
      Eigen::Matrix3d axes;
      axes << x, -y, 0, y, x, 0, 0, 0, 1;  // columns: hi, lo, zz
      const auto k = descending(v);
      for (int a = 0; a < 3; ++a) out.values[a] = v[k[a]], out.axes.col(a) = axes.col(k[a]);
    } else {
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
      eig.computeDirect(to_eigen(s));  // ascending eigenvalues
      out.values = {eig.eigenvalues()(2), eig.eigenvalues()(1), eig.eigenvalues()(0)};
      out.axes = eig.eigenvectors().rowwise().reverse();
    }
    out.tolerance = tolerance_of(out.values);
    return out;
  }

  template <int D>
  void update(const suffuse::StressBatch& batch, const MohrCoulombReturn& ret) const {
    namespace t = suffuse::tensor;
    suffuse::PointSet& pts = batch.points;
    double* stress = pts.data(pts.core().stress);
    double* plastic = pts.data(plastic_strain_);
    double* yielding = pts.data(yielding_);
    double* trial_stress = pts.data(trial_stress_);
    double* e = state_ ? pts.data(e_) : nullptr;
    double* psi = state_ ? pts.data(state_parameter_) : nullptr;
    double* friction = state_ ? pts.data(friction_) : nullptr;
    // The state friction's state after the step: the void ratio follows the
    // step's whole volume change (tension positive; an eigenstrain's too),
    // the state parameter the new p'.
    auto follow_state = [&](std::size_t p, const t::Matrix& d) {
      if (!state_) return;
      double volume = d[0][0] + d[1][1] + d[2][2];
      if (!batch.eigenstrain.empty()) {
        const double* eig = batch.eigenstrain.data() + (p - batch.range.begin) * 6;
        volume += eig[0] + eig[1] + eig[2];
      }
      e[p] = (1 + e[p]) * std::exp(volume) - 1;
      psi[p] = state_->state_parameter(e[p], t::mean_stress(stress + p * 6));
    };
    const suffuse::StepIncrements<D> increments(batch);
    std::optional<MohrCoulombReturn> own;  // a point's own friction, from the state at the step's start
    for (std::size_t p = batch.range.begin; p < batch.range.end; ++p) {
      const auto [d, w] = increments(p);
      double* s6 = stress + p * 6;
      if (state_) {
        const double phi = state_->friction(e[p], t::mean_stress(s6));
        friction[p] = phi / degree;
        own.emplace(return_for(batch.strength_reduction, phi));
      }
      const MohrCoulombReturn& r = own ? *own : ret;
      const t::Matrix trial = t::jaumann_elastic_increment(t::to_matrix(s6), d, w, G_, lambda_);
      const Vec3 values = principal_values(trial);
      if (r.admissible(values, tolerance_of(values))) {
        t::store(trial, s6);
        yielding[p] = 0;
        follow_state(p, d);
        continue;
      }
      const PrincipalAxes pa = principal_axes(trial);
      const Vec3& principal = pa.values;
      t::store(trial, trial_stress + p * 6);
      const Vec3 s = r(principal, pa.tolerance).stress;
      // Back to the axes of the trial stress; the plastic strain is D^-1 of the stress removed.
      const Vec3 removed = {principal[0] - s[0], principal[1] - s[1], principal[2] - s[2]};
      const double tr = removed[0] + removed[1] + removed[2];
      Vec3 de;
      for (int i = 0; i < 3; ++i) de[i] = ((1 + nu_) * removed[i] - nu_ * tr) / E_;
      t::Matrix next{}, dep{};
      for (int a = 0; a < 3; ++a) {
        const auto v = pa.axes.col(a);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            next[i][j] += s[a] * v(i) * v(j);
            dep[i][j] += de[a] * v(i) * v(j);
          }
      }
      t::store(next, s6);
      double* ep = plastic + p * 6;
      const t::Voigt add = t::to_voigt(dep);
      for (int c = 0; c < 6; ++c) ep[c] += add[c];
      yielding[p] = 1;
      follow_state(p, d);
    }
  }

  // The derivative of the returned stress by the strain increment, 6x6 in
  // the form Phase::tangent returns, from the trial stress. In the principal
  // axes the normal components follow principal_tangent; a shear component
  // ab turns the axes, and the stress follows with the modulus
  // G (s_a - s_b) / (s_a^trial - s_b^trial) (its limit where the trial's
  // s_a = s_b).
  void plastic_tangent(const MohrCoulombReturn& ret, const suffuse::tensor::Matrix& trial, double* D) const {
    const PrincipalAxes pa = principal_axes(trial);
    const auto r = ret(pa.values, pa.tolerance);
    const std::array<double, 9> Dp = ret.principal_tangent(r);
    double shear[3][3] = {};
    for (int a = 0; a < 3; ++a)
      for (int b = a + 1; b < 3; ++b) {
        const double gap = pa.values[a] - pa.values[b];
        shear[a][b] = shear[b][a] = gap > 1e-9 * (std::abs(pa.values[a]) + std::abs(pa.values[b]) + cohesion_)
                                        ? G_ * (r.stress[a] - r.stress[b]) / gap
                                        : (Dp[a * 3 + a] - Dp[a * 3 + b] - Dp[b * 3 + a] + Dp[b * 3 + b]) / 4;
      }
    static constexpr int first[6] = {0, 1, 2, 1, 0, 0}, second[6] = {0, 1, 2, 2, 2, 1};
    const Eigen::Matrix3d& v = pa.axes;
    for (int c = 0; c < 6; ++c) {
      // A unit engineering strain of component c, in the principal axes.
      const int i = first[c], j = second[c];
      Eigen::Matrix3d e;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) e(a, b) = i == j ? v(i, a) * v(i, b) : 0.5 * (v(i, a) * v(j, b) + v(j, a) * v(i, b));
      Eigen::Matrix3d ds;  // the stress it gives, in the principal axes
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          ds(a, b) = a == b ? Dp[a * 3] * e(0, 0) + Dp[a * 3 + 1] * e(1, 1) + Dp[a * 3 + 2] * e(2, 2)
                            : 2 * shear[a][b] * e(a, b);
      const Eigen::Matrix3d global = v * ds * v.transpose();
      for (int row = 0; row < 6; ++row) D[row * 6 + c] = global(first[row], second[row]);
    }
  }

  double rho_, nu_, E_, G_, lambda_, cohesion_, phi_, psi_;
  std::optional<double> tensile_strength_;
  MohrCoulombReturn return_;
  std::optional<suffuse_mohr_coulomb::StateFriction> state_;  // state_friction_slope
  double e0_ = 0;
  suffuse::FieldId e_ = 0, state_parameter_ = 0, friction_ = 0;
  suffuse::FieldId plastic_strain_ = 0, yielding_ = 0, trial_stress_ = 0;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::Phase, MohrCoulomb>(
      "phase/mohr_coulomb",
      "Elastic-perfectly plastic Mohr-Coulomb with dilatancy and tension cut-off, exact return in principal stresses");
}
