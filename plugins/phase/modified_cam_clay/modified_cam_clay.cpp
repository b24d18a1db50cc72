// phase/modified_cam_clay: the critical-state model of Roscoe and Burland
// (1968) with the void ratio as state, integrated implicitly (backward Euler,
// Newton on the mean stress, the preconsolidation pressure and the plastic
// multiplier, converging quadratically to 1e-12 relative).
//
// Compression positive in the model (p', q, eps_v, p_c), tension positive in
// the stored stress, as everywhere in the core:
//   yield          f = q^2 / M^2 + p' (p' - p_c) <= 0, associated flow
//   elasticity     -dv^e = kappa d ln p', shear modulus from Poisson's ratio
//                  (G = 3 K (1 - 2 nu) / (2 (1 + nu)), K = v p' / kappa at the
//                  start of the step) or given, Jaumann rate for the deviator
//   hardening      -dv^p = (lambda - kappa) d ln p_c
//   (both exact over a step in v, -dv = v_n (1 - exp(-d eps_v)))
//   lines          NCL v = N - lambda ln(p'/p_ref), CSL v = Gamma - lambda
//                  ln(p'/p_ref), Gamma = N - (lambda - kappa) ln 2
// v = 1 + e, the specific volume, follows the total volumetric strain.
#include <algorithm>
#include <cmath>
#include <string>
#include <suffuse/error.hpp>
#include <suffuse/plugin.hpp>
#include <suffuse/tensor.hpp>

namespace {

class ModifiedCamClay final : public suffuse::Phase {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("density").with_unit("kg/m^3").above(0).doc("Mass density (of the grains in a saturated body)");
    s.number("lambda").with_unit("-").above(0).doc("Slope lambda of the normal compression line in v - ln p'");
    s.number("kappa").with_unit("-").above(0).doc("Slope kappa of the unloading-reloading lines, below lambda");
    s.number("critical_state_ratio").with_unit("-").above(0).doc("M, the stress ratio q/p' at critical state");
    s.number("N").with_unit("-").above(1).may_be_absent().doc(
        "Specific volume v = 1 + e on the normal compression line at p' = reference_pressure (or Gamma)");
    s.number("Gamma").with_unit("-").above(1).may_be_absent().doc(
        "Specific volume on the critical-state line at p' = reference_pressure (or N)");
    s.number("reference_pressure").with_unit("Pa").above(0).fallback(1.0e3).doc(
        "Pressure at which N and Gamma are given (1 kPa, as in most tables)");
    s.number("poisson_ratio").with_unit("-").above(-1).below(0.5).fallback(0.3).doc(
        "Poisson's ratio: the shear modulus follows the pressure-dependent bulk modulus");
    s.number("shear_modulus").with_unit("Pa").above(0).may_be_absent().doc(
        "Constant shear modulus G instead of Poisson's ratio");
    s.number("overconsolidation_ratio").with_unit("-").at_least(1).fallback(1.0).doc(
        "Initial p_c / p'_0, p'_0 each point's initial mean effective stress (or preconsolidation_pressure)");
    s.number("preconsolidation_pressure").with_unit("Pa").above(0).may_be_absent().doc(
        "Initial p_c, the same at every point, instead of the overconsolidation ratio");
    s.number("minimum_mean_stress").with_unit("Pa").above(0).fallback(1.0e3).doc(
        "Smallest p': a point with less confinement, at the start or after unloading (a free surface), has the "
        "isotropic part of its stress raised to it (the model has no stiffness or strength at p' = 0)");
    return s;
  }

  static std::vector<suffuse::ParameterIssue> check(const suffuse::Parameters& p, int) {
    std::vector<suffuse::ParameterIssue> issues;
    if (p.has("N") == p.has("Gamma"))
      issues.push_back({"", "no unique position of the lines", "either \"N\" or \"Gamma\"",
                        p.has("N") ? "both" : "neither"});
    if (p.number("kappa") >= p.number("lambda"))
      issues.push_back({"kappa", "kappa not below lambda", "kappa < lambda = " + std::to_string(p.number("lambda")),
                        std::to_string(p.number("kappa"))});
    if (p.has("preconsolidation_pressure") && p.number("overconsolidation_ratio") != 1.0)
      issues.push_back({"preconsolidation_pressure", "two initial preconsolidations",
                        "either preconsolidation_pressure or overconsolidation_ratio", "both"});
    return issues;
  }

  explicit ModifiedCamClay(const suffuse::PluginArgs& a)
      : rho_(a.params.number("density")),
        lambda_(a.params.number("lambda")),
        kappa_(a.params.number("kappa")),
        M_(a.params.number("critical_state_ratio")),
        p_ref_(a.params.number("reference_pressure")),
        nu_(a.params.number("poisson_ratio")),
        G_(a.params.has("shear_modulus") ? a.params.number("shear_modulus") : 0.0),
        ocr_(a.params.number("overconsolidation_ratio")),
        pc0_(a.params.has("preconsolidation_pressure") ? a.params.number("preconsolidation_pressure") : 0.0),
        p_min_(a.params.number("minimum_mean_stress")),
        where_(a.instance) {
    N_ = a.params.has("N") ? a.params.number("N") : a.params.number("Gamma") + (lambda_ - kappa_) * std::log(2.0);
  }

  double density() const override { return rho_; }
  // The stiffest initial state (initialise() records it): K = v p' / kappa
  // grows with p', so a run that compresses the soil far beyond its initial
  // state needs a smaller /time/dt or cfl than the automatic one.
  double p_wave_modulus() const override {
    const double K = std::max(stiffest_bulk_modulus_, 2 * p_min_ / kappa_);
    return K + 4.0 / 3.0 * shear(K);
  }

  void add_fields(suffuse::PointSet& points) override {
    using K = suffuse::FieldKind;
    e_ = points.add_field({"void_ratio", K::Scalar, "-", "void ratio e", true});
    pc_ = points.add_field({"preconsolidation_pressure", K::Scalar, "Pa", "p_c, compression positive", true});
    p_ = points.add_field({"mean_effective_stress", K::Scalar, "Pa", "p', compression positive", true});
    q_ = points.add_field({"deviatoric_stress", K::Scalar, "Pa", "q = sqrt(3 J2)", true});
    eta_ = points.add_field({"stress_ratio", K::Scalar, "-", "eta = q / p'", true});
    psi_ = points.add_field({"state_parameter", K::Scalar, "-", "psi = e - e_cs(p'): positive looser than critical", true});
    // What the consistent tangent needs of the last return (tangent()).
    trial_ = points.add_field({"cam_clay_trial_deviator", K::SymmetricTensor, "Pa",
                               "the deviator of the last step's elastic trial stress", false});
    dv_ = points.add_field({"cam_clay_step_compression", K::Scalar, "-",
                            "-dv / v_n of the last step, 1 - exp(-d eps_v)", false});
    G_step_ = points.add_field({"cam_clay_step_shear_modulus", K::Scalar, "Pa", "G of the last step", false});
    dl_ = points.add_field({"cam_clay_plastic_multiplier", K::Scalar, "Pa^-1",
                            "the last step's plastic multiplier (0: elastic)", false});
  }

  void initialise(suffuse::PointSet& points, suffuse::PointRange range) const override {
    double* s = points.data(points.core().stress);
    for (std::size_t p = range.begin; p < range.end; ++p) {
      // A point with less confinement than the minimum starts at it: the
      // isotropic part of its stress is raised, so stress and state agree.
      const double raise = p_min_ - suffuse::tensor::mean_stress(s + p * 6);
      if (raise > 0)
        for (int c = 0; c < 3; ++c) s[p * 6 + c] -= raise;
      const double p0 = suffuse::tensor::mean_stress(s + p * 6);
      const double q0 = suffuse::tensor::deviatoric_stress(s + p * 6);
      double pc = pc0_ > 0 ? pc0_ : ocr_ * p0;
      pc = std::max(pc, p0 + q0 * q0 / (M_ * M_ * p0));  // on or inside the yield surface
      // On the unloading line through (p_c, v_NCL(p_c)).
      const double v = N_ - lambda_ * std::log(pc / p_ref_) + kappa_ * std::log(pc / p0);
      points.data(e_)[p] = v - 1;
      points.data(pc_)[p] = pc;
      report(points, p, p0, q0, v);
      stiffest_bulk_modulus_ = std::max(stiffest_bulk_modulus_, v * p0 / kappa_);
    }
  }

  // The consistent tangent of the last step's return: the derivative of the
  // returned stress by the strain increment (the spin's rotation of the old
  // deviator left out), so that the quasi-static iterations converge
  // quadratically. Elastic: K = v p' / kappa at the step's end and the
  // step's G. Plastic: the implicit function theorem on the return's
  // residuals r(p', p_c, dl; dv, q_tr) = 0 at the converged state gives
  // dp' and d dl from d dv = -(1 - dv) tr(d eps) and
  // dq_tr = (3 G / q_tr) s_tr : d eps; the stress is s_tr / (1 + c dl) - p' I.
  bool tangent(const suffuse::StressBatch& b, std::span<double> stiffness) const override {
    namespace t = suffuse::tensor;
    const suffuse::PointSet& pts = b.points;
    const double* stress = pts.data(pts.core().stress);
    const double *e = pts.data(e_), *pcs = pts.data(pc_), *trial = pts.data(trial_), *dvs = pts.data(dv_),
                 *Gs = pts.data(G_step_), *dls = pts.data(dl_);
    const double M2 = M_ * M_;
    for (std::size_t i = b.range.begin; i < b.range.end; ++i) {
      double* D = stiffness.data() + (i - b.range.begin) * 36;
      const double p = std::max(p_min_, t::mean_stress(stress + i * 6));
      const double dv = dvs[i], G = Gs[i] > 0 ? Gs[i] : shear((1 + e[i]) * p / kappa_);
      const double v_n = (1 + e[i]) / (1 - dv), a = v_n / kappa_;
      const double L = dls[i];
      if (!(L > 0)) {  // elastic: p' = p_n exp(a dv), the deviator by Hooke
        t::isotropic_stiffness(a * p * (1 - dv), G, D);
        continue;
      }
      const double* s = trial + i * 6;
      const double q_tr = std::sqrt(1.5 * t::double_contraction(s, s));
      const double pc = pcs[i], theta = v_n / (lambda_ - kappa_), c = 6 * G / M2, h = 2 * p - pc;
      const double Q = q_tr / (1 + c * L), dQ = -q_tr * c / ((1 + c * L) * (1 + c * L));
      // The return's Jacobian at convergence (A = p', B = p_c there).
      const double J[3][3] = {{1 + p * a * 2 * L, -p * a * L, p * a * h},
                              {-pc * theta * 2 * L, 1 + pc * theta * L, -pc * theta * h},
                              {2 * p - pc, -p, 2 * Q * dQ / M2}};
      const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
                         J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                         J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
      // The first and last rows of J^-1 (cofactors over det).
      const double inv00 = (J[1][1] * J[2][2] - J[1][2] * J[2][1]) / det,
                   inv02 = (J[0][1] * J[1][2] - J[0][2] * J[1][1]) / det,
                   inv20 = (J[1][0] * J[2][1] - J[1][1] * J[2][0]) / det,
                   inv22 = (J[0][0] * J[1][1] - J[0][1] * J[1][0]) / det;
      const double r_q = 2 * Q / (M2 * (1 + c * L));  // d r_yield / d q_tr
      const double p_dv = inv00 * p * a, p_dq = -inv02 * r_q, L_dv = inv20 * p * a, L_dq = -inv22 * r_q;
      // d dv / d eps = -(1 - dv) m, d q_tr / d eps = (3 G / q_tr) s_tr (engineering shear).
      const double k_q = q_tr > 0 ? 3 * G / q_tr : 0.0;
      t::isotropic_stiffness(0.0, G / (1 + c * L), D);  // 2 G dev(d eps) / (1 + c dl)
      const double f = -c / ((1 + c * L) * (1 + c * L));
      for (int r = 0; r < 6; ++r)
        for (int col = 0; col < 6; ++col) {
          const double m_col = col < 3 ? 1.0 : 0.0, m_row = r < 3 ? 1.0 : 0.0;
          const double d_dv = -(1 - dv) * m_col, d_q = k_q * s[col];
          D[r * 6 + col] += f * s[r] * (L_dv * d_dv + L_dq * d_q) - m_row * (p_dv * d_dv + p_dq * d_q);
        }
    }
    return true;
  }
  void update_stress(const suffuse::StressBatch& b) const override {
    if (b.points.dim() == 2)
      update<2>(b);
    else
      update<3>(b);
  }

 private:
  double shear(double K) const { return G_ > 0 ? G_ : 1.5 * K * (1 - 2 * nu_) / (1 + nu_); }
  double critical_v(double p) const { return N_ - (lambda_ - kappa_) * std::log(2.0) - lambda_ * std::log(p / p_ref_); }

  void report(suffuse::PointSet& points, std::size_t i, double p, double q, double v) const {
    points.data(p_)[i] = p;
    points.data(q_)[i] = q;
    points.data(eta_)[i] = q / p;
    points.data(psi_)[i] = v - critical_v(p);
  }

  template <int D>
  void update(const suffuse::StressBatch& b) const {
    namespace t = suffuse::tensor;
    suffuse::PointSet& pts = b.points;
    double* stress = pts.data(pts.core().stress);
    double* e = pts.data(e_);
    double* pcs = pts.data(pc_);
    const suffuse::StepIncrements<D> increments(b);
    for (std::size_t i = b.range.begin; i < b.range.end; ++i) {
      const auto [d, w] = increments(i);
      double* s6 = stress + i * 6;
      double v_n = 1 + e[i], pc_n = pcs[i];
      if (!b.eigenstrain.empty()) {
        // An eigenstrain (a wrapping phase's, e.g. erosion-induced) is
        // inelastic: its volume change moves v at constant p' along the
        // plastic lines, -dv = (lambda - kappa) d ln p_c, so p_c hardens with
        // its compaction and softens with its dilation.
        const double eig = t::volumetric_strain(b.eigenstrain.data() + (i - b.range.begin) * 6);
        const double dv = 1 - std::exp(-eig);  // -dv / v_n
        pc_n *= std::exp(v_n * dv / (lambda_ - kappa_));
        v_n *= 1 - dv;
      }
      // A point unloaded below the minimum mean stress (a free surface) is
      // brought back to it, isotropically, in its stress too: the model has
      // no stiffness at p' = 0.
      const double raise = p_min_ - t::mean_stress(s6);
      if (raise > 0)
        for (int c = 0; c < 3; ++c) s6[c] -= raise;
      const double p_n = t::mean_stress(s6);
      const double K = v_n * p_n / kappa_, G = shear(K);
      const double dev = -(d[0][0] + d[1][1] + d[2][2]);  // compression positive
      // Elastic trial: the deviator by Hooke with the Jaumann rate, p' exactly on the unloading line.
      const t::Matrix s_old = t::to_matrix(s6);
      t::Matrix dev_trial = t::jaumann_elastic_increment(s_old, d, w, G, -2.0 * G / 3.0);  // tr part removed below
      const double m = (dev_trial[0][0] + dev_trial[1][1] + dev_trial[2][2]) / 3;
      for (int k = 0; k < 3; ++k) dev_trial[k][k] -= m;
      const t::Voigt s_tr = t::to_voigt(dev_trial);
      const double q_tr = std::sqrt(1.5 * t::double_contraction(s_tr.data(), s_tr.data()));
      // -dv / v_n = 1 - exp(-d eps_v): the change of specific volume the lines are written in.
      const double dv = 1 - std::exp(-dev);
      const double p_tr = p_n * std::exp(v_n * dv / kappa_);
      double p = p_tr, pc = pc_n, q = q_tr, dl = 0;
      if (q_tr * q_tr / (M_ * M_) + p_tr * (p_tr - pc_n) > 1e-12 * pc_n * pc_n)
        dl = return_map(p_n, pc_n, v_n, dv, q_tr, G, p, pc, q, i);
      std::copy(s_tr.begin(), s_tr.end(), pts.data(trial_) + i * 6);
      pts.data(dv_)[i] = dv;
      pts.data(G_step_)[i] = G;
      pts.data(dl_)[i] = dl;
      const double scale = q_tr > 0 ? q / q_tr : 0.0;
      for (int c = 0; c < 6; ++c) s6[c] = scale * s_tr[c] - (c < 3 ? p : 0.0);
      const double v = v_n * std::exp(-dev);
      e[i] = v - 1;
      pcs[i] = pc;
      report(pts, i, p, q, v);
    }
  }

  // Backward Euler on (p', p_c, dl): the elastic law, the hardening and the
  // yield condition; Newton with the exact Jacobian, halved steps if an
  // iterate leaves p', p_c > 0, dl >= 0. `dev` is -dv / v_n of the step; the
  // plastic part of it is dl (2 p' - p_c), so v stays on the lines exactly:
  // -dv = kappa d ln p' + (lambda - kappa) d ln p_c.
  // Returns the plastic multiplier.
  double return_map(double p_n, double pc_n, double v, double dev, double q_tr, double G, double& p, double& pc,
                    double& q, std::size_t point) const {
    const double M2 = M_ * M_, a = v / kappa_, theta = v / (lambda_ - kappa_), c = 6 * G / M2;
    double dl = 0;
    auto residual = [&](double P, double Pc, double L, double r[3], double J[3][3]) {
      const double h = 2 * P - Pc, A = p_n * std::exp(a * (dev - L * h)), B = pc_n * std::exp(theta * L * h);
      const double Q = q_tr / (1 + c * L), dQ = -q_tr * c / ((1 + c * L) * (1 + c * L));
      r[0] = P - A;
      r[1] = Pc - B;
      r[2] = Q * Q / M2 + P * (P - Pc);
      J[0][0] = 1 + A * a * 2 * L, J[0][1] = -A * a * L, J[0][2] = A * a * h;
      J[1][0] = -B * theta * 2 * L, J[1][1] = 1 + B * theta * L, J[1][2] = -B * theta * h;
      J[2][0] = 2 * P - Pc, J[2][1] = -P, J[2][2] = 2 * Q * dQ / M2;
    };
    for (int iteration = 0; iteration < 60; ++iteration) {
      double r[3], J[3][3];
      residual(p, pc, dl, r, J);
      if (std::abs(r[0]) <= 1e-12 * p && std::abs(r[1]) <= 1e-12 * pc && std::abs(r[2]) <= 1e-12 * pc * pc) {
        q = q_tr / (1 + c * dl);
        return dl;
      }
      // Solve J dx = -r (Cramer's rule: 3x3).
      const double det = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
                         J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
                         J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
      double dx[3];
      for (int k = 0; k < 3; ++k) {
        double Jk[3][3];
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) Jk[i][j] = j == k ? -r[i] : J[i][j];
        dx[k] = (Jk[0][0] * (Jk[1][1] * Jk[2][2] - Jk[1][2] * Jk[2][1]) -
                 Jk[0][1] * (Jk[1][0] * Jk[2][2] - Jk[1][2] * Jk[2][0]) +
                 Jk[0][2] * (Jk[1][0] * Jk[2][1] - Jk[1][1] * Jk[2][0])) /
                det;
      }
      double step = 1;
      while (step > 1e-6 && (p + step * dx[0] <= 0 || pc + step * dx[1] <= 0 || dl + step * dx[2] < 0)) step /= 2;
      if (p + step * dx[0] <= 0 || pc + step * dx[1] <= 0 || dl + step * dx[2] < 0) break;  // no admissible step
      p += step * dx[0], pc += step * dx[1], dl += step * dx[2];
    }
    throw suffuse::Error(where_ + " (phase/modified_cam_clay): the return mapping did not converge at material point " +
                         std::to_string(point) + " (p' = " + std::to_string(p) + " Pa, p_c = " + std::to_string(pc) +
                         " Pa); reduce the time step");
  }

  double rho_, lambda_, kappa_, M_, p_ref_, nu_, G_, ocr_, pc0_, p_min_, N_;
  // Set-up only (initialise runs once per body, on one thread), for p_wave_modulus().
  mutable double stiffest_bulk_modulus_ = 0;
  std::string where_;
  suffuse::FieldId e_ = 0, pc_ = 0, p_ = 0, q_ = 0, eta_ = 0, psi_ = 0, trial_ = 0, dv_ = 0, G_step_ = 0, dl_ = 0;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::Phase, ModifiedCamClay>(
      "phase/modified_cam_clay",
      "Modified Cam-Clay critical-state skeleton with the void ratio as state, implicit return mapping");
}
