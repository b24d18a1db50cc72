// phase/suffosion: the deformation of a soil skeleton as its fines wash out
// (suffosion), after the DEM study of gap-graded soils in seed 001 (the
// relations and fitted values: docs/suffosion.md). It wraps a base skeleton
// (phase/modified_cam_clay, phase/mohr_coulomb, ...), given under "base",
// and adds an erosion-induced plastic strain, written as an eigenstrain, from
// each point's eroded fraction f_er and its stress ratio eta = q/p' at the
// start of the step:
//
//   onset      none while f_er < f_so(eta), (f_so/f_so0)^2 + (eta/M_so)^2 = 1
//              (f_so = 0 for eta >= M_so); a step that crosses it counts only
//              the part of its increment beyond f_so
//   volume     d eps_v = A [1 - (eta/M_c)^xi] d f_er, compression positive
//   shear      d eps_s = d eps_v / D, D = (M_c^2 - eta^2) / (beta eta), along
//              the deviatoric stress
//
// The stress ratio of a step ("integration"): explicit, the step's start
// (the study's law as written, for steps that erode little: explicit runs,
// the element tests); substeps, the ratio each substep of the step's erosion
// leaves the point at, its total strain held (relax() below). That
// relaxation is stiff where the confinement is low (a shear strain of 1e-3
// relaxes q by 3 G 1e-3, 23 kPa at E = 20 MPa, against a p' of a few kPa),
// and a quasi-static step that erodes 1e-3 of the solid at the step's
// starting ratio overshoots it (docs/time-integration.md, Limits).
// implicit: backward Euler, the ratio of the step's end, inside the stress
// update: a quasi-static step's equilibrium carries the erosion-induced
// strain of its own stresses, and its tangent the strain's dependence on
// them (update_stress_eroding() below). A point its neighbours hold up
// keeps its stress and takes the law's full strain of the step's erosion,
// which "substeps", relaxing it from the step's start as if nothing held
// it, caps at the point's slack (a levee's eroding ground settled more the
// more steps it took: docs/time-integration.md).
//
// The void ratio follows the fines lost: e = (1 + e_0) exp(-eps_v) / (1 -
// f_er) - 1, eps_v the skeleton's accumulated volumetric strain (the study's
// e = (e_0 + f_er)/(1 - f_er) - eps_v (e_0 + 1)/(1 - f_er) to first order in
// eps_v, and without erosion the exact void ratio a critical-state base
// integrates). A base that tracks "void_ratio" (and "state_parameter") has
// them set to it; its hardening counts the eigenstrain (Modified Cam-Clay:
// p_c follows the erosion-induced compaction along its lines).
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <vector>
#include <suffuse/error.hpp>
#include <suffuse/plugin.hpp>
#include <suffuse/tensor.hpp>

#include "implicit_erosion.hpp"
#include "suffosion_law.hpp"

namespace {

namespace t = suffuse::tensor;
using suffosion::add;
using suffosion::Direction;
using suffosion::stress_of;
using suffosion::strain_tensor;
using suffosion::SuffosionLaw;

class Suffosion final : public suffuse::Phase {
 public:
  static constexpr bool wraps_base_phase = true;

  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("onset_ratio").with_unit("-").above(0).fallback(0.71).doc(
        "M_so: the stress ratio at and above which erosion deforms the skeleton from the first fines lost");
    s.number("onset_fraction").with_unit("-").at_least(0).below(1).fallback(0.02).doc(
        "f_so0: the eroded fraction at which erosion starts to deform an isotropically loaded skeleton (eta = 0)");
    s.number("critical_ratio").with_unit("-").above(0).fallback(0.86).doc(
        "M_c: the stress ratio of the erosion-induced strain's sign change (compaction below, dilation above) and of "
        "its dilatancy D = 0");
    s.number("compaction_rate").with_unit("-").at_least(0).fallback(0.85).doc(
        "A: d eps_v / d f_er at eta = 0");
    s.number("compaction_exponent").with_unit("-").above(0).fallback(8.0).doc(
        "xi: d eps_v / d f_er = A [1 - (eta/M_c)^xi]");
    s.number("dilatancy_factor").with_unit("-").above(0).fallback(1.5).doc(
        "beta: erosion dilatancy D = d eps_v / d eps_s = (M_c^2 - eta^2) / (beta eta) (Modified Cam-Clay's "
        "loading has 2)");
    s.number("stress_ratio_limit").with_unit("-").above(0).fallback(1.0).doc(
        "eta above it is taken as it: the study's data reach 0.93, and the fits grow fast beyond (at a free "
        "surface p' tends to zero and eta to infinity)");
    s.choice("integration", {"explicit", "substeps", "implicit"}).fallback(std::string("explicit")).doc(
        "How a step's erosion-induced strain is integrated. explicit: at the stress ratio of the step's start (the "
        "study's law as written; right where a step erodes little, as in explicit runs and the element tests). "
        "substeps: in substeps at the point's held total strain, each at the stress ratio the last left (the "
        "point's own relaxation, with the base's elastic stiffness), from the step's start. implicit: at the "
        "stress ratio of the step's end (backward Euler), found in each stress update with the step's strain, and "
        "with its consistent tangent: a quasi-static step's equilibrium then carries the strain of its own "
        "stresses, and its result converges as the steps shrink (substeps caps a step's strain at the point's "
        "slack)");
    s.number("initial_void_ratio").with_unit("-").above(0).may_be_absent().doc(
        "e_0, for a base that tracks no void ratio (phase/mohr_coulomb): the phase then reports void_ratio. A base "
        "that tracks one (phase/modified_cam_clay) gives e_0 at each point, and this is not used");
    return s;
  }

  static std::vector<std::string> required_fields(const suffuse::Parameters&, int) {
    return {suffuse::coupling::eroded_fraction, suffuse::coupling::eroded_fraction_increment};
  }

  explicit Suffosion(const suffuse::PluginArgs& a)
      : base_(a.base),
        law_{a.params.number("onset_ratio"),         a.params.number("onset_fraction"),
             a.params.number("critical_ratio"),      a.params.number("compaction_rate"),
             a.params.number("compaction_exponent"), a.params.number("dilatancy_factor"),
             a.params.number("stress_ratio_limit")},
        substeps_(a.params.string("integration") == "substeps"),
        implicit_(a.params.string("integration") == "implicit"),
        e0_given_(a.params.maybe_number("initial_void_ratio")),
        where_(a.instance) {
    if (!base_) throw suffuse::Error(a.instance + ": phase/suffosion needs a base phase (\"base\")");
  }

  double density() const override { return base_->density(); }
  double p_wave_modulus() const override { return base_->p_wave_modulus(); }

  void add_fields(suffuse::PointSet& points) override {
    using K = suffuse::FieldKind;
    f_ = points.id(suffuse::coupling::eroded_fraction);
    df_ = points.id(suffuse::coupling::eroded_fraction_increment);
    ev_ = points.add_field({"erosion_volumetric_strain", K::Scalar, "-",
                            "erosion-induced volumetric strain, accumulated, compression positive", true});
    es_ = points.add_field({"erosion_shear_strain", K::Scalar, "-",
                            "erosion-induced shear strain eps_s, accumulated (increments summed)", true});
    onset_ = points.add_field({"suffosion_onset", K::Scalar, "-",
                               "f_so(eta) at the last step: the eroded fraction at which erosion deforms the point", true});
    e0_ = points.add_field({"initial_void_ratio", K::Scalar, "-", "e_0 of the void-ratio identity (0: none)", false});
    base_e_ = points.add_field(
        {"base_tracks_void_ratio", K::Scalar, "-", "1 where the base phase tracks the void ratio", false});
    // Fields are shared by name across materials: whether the base tracks
    // "void_ratio" is known once it has initialised its points.
    e_ = points.find("void_ratio");
    if (!e_ && e0_given_)
      e_ = points.add_field({"void_ratio", K::Scalar, "-", "void ratio e, with the fines lost", true});
    psi_ = points.find("state_parameter");
    eigenstrain_ = points.find("eigenstrain");
    eigenstrain_increment_ = points.find("eigenstrain_increment");
    if (implicit_) {
      // For the tangent (update_stress_eroding()).
      volumetric_gradient_ = points.add_field({"erosion_volumetric_strain_gradient", K::SymmetricTensor, "-",
                                               "implicit: d(the step's d eps_v)/d eps (engineering shear)", false});
      shear_gradient_ = points.add_field({"erosion_shear_strain_gradient", K::SymmetricTensor, "-",
                                          "implicit: d(the step's d eps_s)/d eps (engineering shear)", false});
      shear_direction_ = points.add_field({"erosion_shear_direction", K::SymmetricTensor, "-",
                                           "implicit: the strain of a unit d eps_s", false});
    }
  }

  void initialise(suffuse::PointSet& points, suffuse::PointRange range) const override {
    base_->initialise(points, range);
    const double* stress = points.data(points.core().stress);
    for (std::size_t p = range.begin; p < range.end; ++p) points.data(onset_)[p] = onset_at(stress + p * 6);
    if (!e_) return;
    double* e = points.data(*e_);
    double* e0 = points.data(e0_);
    double* base_e = points.data(base_e_);
    for (std::size_t p = range.begin; p < range.end; ++p) {
      // A base that tracks the void ratio wrote a positive one; else the
      // phase's own e_0, if given; else none (e_0 = 0: the point is skipped).
      base_e[p] = e[p] > 0 ? 1.0 : 0.0;
      if (!(e[p] > 0)) e[p] = e0_given_.value_or(0.0);
      e0[p] = e[p];
    }
  }

  bool writes_eigenstrain() const override { return true; }

  // The base's own eigenstrain, if it writes one, plus the erosion-induced one.
  // ("implicit": the base's only; update_stress adds the erosion's.)
  void eigenstrain(const suffuse::StressBatch& b, std::span<double> increment) const override {
    if (base_->writes_eigenstrain()) base_->eigenstrain(b, increment);
    if (implicit_) return;
    suffuse::PointSet& pts = b.points;
    const double* stress = pts.data(pts.core().stress);
    const double* f = pts.data(f_);
    const double* df = pts.data(df_);
    double* ev = pts.data(ev_);
    double* es = pts.data(es_);
    double* onset = pts.data(onset_);
    std::vector<double> stiffness;  // substeps: the base's elastic stiffness, 36 per point
    if (substeps_) elastic_stiffness_of(b, stiffness);
    for (std::size_t p = b.range.begin; p < b.range.end; ++p) {
      const double* s = stress + p * 6;
      const double mean = t::mean_stress(s), q = t::deviatoric_stress(s);
      if (!(mean > 0)) {  // no confinement: no skeleton stress to deform under
        onset[p] = 1.0;
        continue;
      }
      const double eta = std::min(q / mean, law_.eta_max);
      const t::Voigt dev = t::deviator(s);
      SuffosionLaw::Strain d;
      t::Voigt e;
      if (substeps_ && f[p] - std::max(f[p] - df[p], 0.0) > 0) {  // erodes past the lowest onset (0)
        const Relaxed r = relax(s, dev, q, stiffness.data() + (p - b.range.begin) * 36, f[p], df[p]);
        onset[p] = law_.onset(r.eta);
        d = r.strain, e = r.tensor;
      } else {
        onset[p] = law_.onset(eta);
        d = law_.of_step(eta, f[p], df[p]);
        e = strain_tensor(d, dev, q);
      }
      if (d.volumetric == 0 && d.shear == 0) continue;
      ev[p] += d.volumetric;
      es[p] += d.shear;
      double* inc = increment.data() + (p - b.range.begin) * 6;
      for (int c = 0; c < 6; ++c) inc[c] += e[c];
    }
  }

  bool elastic_stiffness(const suffuse::StressBatch& b, std::span<double> stiffness) const override {
    return base_->elastic_stiffness(b, stiffness);
  }

  // The base's: the erosion-induced strain is imposed, not a stiffness;
  // "implicit": less the base's times the derivative of the erosion's strain
  // by the strain increment (soften_tangent()).
  bool tangent(const suffuse::StressBatch& b, std::span<double> stiffness) const override {
    if (!implicit_) return base_->tangent(b, stiffness);
    // (The core's fallback where the base gives none: the correction needs it in hand.)
    if (!base_->tangent(b, stiffness)) isotropic_fallback(b.range.size(), stiffness);
    soften_tangent(b, stiffness);
    return true;
  }
  // The base model's strength is the strength a strength reduction divides
  // (the erosion-induced strain adds none).
  bool reduces_strength() const override { return base_->reduces_strength(); }
  void update_stress(const suffuse::StressBatch& b) const override {
    if (implicit_)
      update_stress_eroding(b);
    else
      base_->update_stress(b);
    if (!e_) return;
    suffuse::PointSet& pts = b.points;
    const double* L = pts.data(pts.core().velocity_gradient);
    const double* f = pts.data(f_);
    const double* df = pts.data(df_);
    const double* e0 = pts.data(e0_);
    const double* base_e = pts.data(base_e_);
    double* e = pts.data(*e_);
    double* psi = psi_ ? pts.data(*psi_) : nullptr;
    const int dim = pts.dim();
    for (std::size_t p = b.range.begin; p < b.range.end; ++p) {
      if (!(e0[p] > 0)) continue;  // no void ratio tracked here
      if (!(f[p] < 1))
        throw suffuse::Error(where_ + " (phase/suffosion): material point " + std::to_string(p) +
                             " has lost all its solid (eroded fraction " + std::to_string(f[p]) + ")");
      // The void-ratio identity over the step: the volume changes by
      // exp(tr(L) dt) (a base that tracks e has moved it so already), the
      // solid by (1 - f) / (1 - f_n). Step by step, from the state at the
      // step's start: a quasi-static step's strain is the core's only once
      // it has converged, and its iterations each start from that state.
      double volume = 0;
      for (int i = 0; i < dim; ++i) volume += L[p * dim * dim + i * dim + i] * b.dt;
      const double moved = base_e[p] > 0 ? 1 + e[p] : (1 + e[p]) * std::exp(volume);
      const double e_new = moved * (1 - (f[p] - df[p])) / (1 - f[p]) - 1;
      if (psi && base_e[p] > 0) psi[p] += e_new - e[p];  // e_cs(p') is the base's: only e moved
      e[p] = e_new;
    }
  }

 private:
  // f_so at a stress (1 where there is no confinement: nothing to deform),
  // as eigenstrain() finds it.
  double onset_at(const double* s) const {
    const double mean = t::mean_stress(s);
    return mean > 0 ? law_.onset(std::min(t::deviatoric_stress(s) / mean, law_.eta_max)) : 1.0;
  }

  // "implicit": each eroding point's strain of the step by erode()
  // (implicit_erosion.hpp: backward Euler from the elastic trial), imposed
  // on the base's update with the base's own eigenstrain. For the tangent,
  // the base's C less C times that strain's derivative with respect to
  // the strain increment (soften_tangent()). That strain is
  // d eps_v along -I/3 and d eps_s along the fixed shear direction, so the
  // derivative is two gradients (kept per point: d(d eps_v)/d eps and
  // d(d eps_s)/d eps, and the shear direction), each by central
  // differences of erode() (twelve more of its solves at an eroding point:
  // the root's movement, the onset's and the slack's share all in it),
  // only where the batch says a tangent follows; else the gradients are
  // zero and a tangent asked anyway is the base's.
  void update_stress_eroding(const suffuse::StressBatch& b) const {
    suffuse::PointSet& pts = b.points;
    const std::size_t n = b.range.size();
    std::vector<double> imposed(n * 6, 0.0), erosion(n * 6, 0.0), stiffness;
    if (!b.eigenstrain.empty()) std::copy(b.eigenstrain.begin(), b.eigenstrain.end(), imposed.begin());
    elastic_stiffness_of(b, stiffness);
    const double* stress = pts.data(pts.core().stress);
    const double* L = pts.data(pts.core().velocity_gradient);
    const double* f = pts.data(f_);
    const double* df = pts.data(df_);
    double* ev = pts.data(ev_);
    double* es = pts.data(es_);
    double* onset = pts.data(onset_);
    double* grad_v = pts.data(volumetric_gradient_);
    double* grad_s = pts.data(shear_gradient_);
    double* shear_direction = pts.data(shear_direction_);
    const int dim = pts.dim();
    for (std::size_t p = b.range.begin; p < b.range.end; ++p) {
      const std::size_t i = p - b.range.begin;
      const double* D = stiffness.data() + i * 36;
      const double* start = stress + p * 6;
      std::fill_n(grad_v + p * 6, 6, 0.0);
      std::fill_n(grad_s + p * 6, 6, 0.0);
      t::Voigt strain{};  // the step's strain increment less the base's eigenstrain (tensor shear)
      for (int r = 0; r < dim; ++r)
        for (int c = r; c < dim; ++c)
          strain[t::voigt_index(r, c)] = 0.5 * (L[p * dim * dim + r * dim + c] + L[p * dim * dim + c * dim + r]) * b.dt;
      for (int c = 0; c < 6; ++c) strain[c] -= imposed[i * 6 + c];
      const t::Voigt trial = add(start, stress_of(D, strain), 1.0);
      const double p_trial = t::mean_stress(trial.data());
      if (!(std::max(t::mean_stress(start), p_trial) > 0)) {  // no confinement: no skeleton stress to deform under
        onset[p] = 1.0;
        continue;
      }
      // q along the start's deviator, or the trial's where the start has none.
      const double q_start = t::deviatoric_stress(start);
      const Direction along = q_start > 0 ? Direction{t::deviator(start), q_start}
                                          : Direction{t::deviator(trial.data()), t::deviatoric_stress(trial.data())};
      if (!(f[p] - std::max(f[p] - df[p], 0.0) > 0)) {  // erodes nothing
        onset[p] = p_trial > 0 ? law_.onset(std::min(std::max(0.0, along.along(trial)) / p_trial, law_.eta_max)) : 1.0;
        continue;
      }
      double eta = 0;
      const SuffosionLaw::Strain d = erode(law_, start, strain, D, along, f[p], df[p], eta);
      onset[p] = law_.onset(eta);
      // The tangent's gradients only where one may be asked for next: not
      // in an explicit step (a quasi-static run's collapse), where they
      // were nearly all of the stress update's time.
      if (b.tangent_follows) {
        constexpr double h = 1e-9;  // of strain: D h is a few hundredths of a pascal
        for (int c = 0; c < 6; ++c) {
          t::Voigt up = strain, down = strain;
          const double step = c < 3 ? h : h / 2;  // an engineering shear strain of h
          up[c] += step, down[c] -= step;
          double unused = 0;
          const SuffosionLaw::Strain a = erode(law_, start, up, D, along, f[p], df[p], unused, eta);
          const SuffosionLaw::Strain z = erode(law_, start, down, D, along, f[p], df[p], unused, eta);
          grad_v[p * 6 + c] = (a.volumetric - z.volumetric) / (2 * h);
          grad_s[p * 6 + c] = (a.shear - z.shear) / (2 * h);
        }
        const t::Voigt unit_shear = strain_tensor({0.0, 1.0}, along.dev, along.q);
        std::copy(unit_shear.begin(), unit_shear.end(), shear_direction + p * 6);
      }
      const t::Voigt e = strain_tensor(d, along.dev, along.q);
      ev[p] += d.volumetric;
      es[p] += d.shear;
      for (int c = 0; c < 6; ++c) imposed[i * 6 + c] += e[c], erosion[i * 6 + c] = e[c];
    }
    base_->update_stress(suffuse::StressBatch{pts, b.range, b.dt, imposed, b.strength_reduction, b.tangent_follows});
    for (const auto& field : {eigenstrain_, eigenstrain_increment_}) {
      if (!field) continue;
      double* total = pts.data(*field) + b.range.begin * 6;
      for (std::size_t k = 0; k < n * 6; ++k) total[k] += erosion[k];
    }
  }

  // C - (C v) d(d eps_v)/d eps - (C s) d(d eps_s)/d eps, v = -I/3 and s the
  // shear direction (engineering shear), C the base's tangent.
  void soften_tangent(const suffuse::StressBatch& b, std::span<double> stiffness) const {
    const suffuse::PointSet& pts = b.points;
    const double* grad_v = pts.data(volumetric_gradient_);
    const double* grad_s = pts.data(shear_gradient_);
    const double* shear_direction = pts.data(shear_direction_);
    const t::Voigt volumetric = strain_tensor({1.0, 0.0}, {}, 0.0);
    for (std::size_t p = b.range.begin; p < b.range.end; ++p) {
      const double* gv = grad_v + p * 6;
      const double* gs = grad_s + p * 6;
      auto zero = [](const double* v) { return std::all_of(v, v + 6, [](double x) { return x == 0; }); };
      if (zero(gv) && zero(gs)) continue;
      double* C = stiffness.data() + (p - b.range.begin) * 36;
      const double* sd = shear_direction + p * 6;
      const t::Voigt Cv = stress_of(C, volumetric), Cs = stress_of(C, {sd[0], sd[1], sd[2], sd[3], sd[4], sd[5]});
      for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 6; ++c) C[r * 6 + c] -= Cv[r] * gv[c] + Cs[r] * gs[c];
    }
  }

  // The base's elastic stiffness of the batch's points, or an isotropic one
  // of its P-wave modulus and Poisson's ratio 0.3 (the core's fallback).
  void elastic_stiffness_of(const suffuse::StressBatch& b, std::vector<double>& D) const {
    D.assign(b.range.size() * 36, 0.0);
    if (!base_->elastic_stiffness(b, D)) isotropic_fallback(b.range.size(), D);
  }
  void isotropic_fallback(std::size_t points, std::span<double> D) const {
    const double nu = 0.3, M = base_->p_wave_modulus();
    const double G = M * (1 - 2 * nu) / (2 * (1 - nu)), K = M - 4 * G / 3;
    for (std::size_t i = 0; i < points; ++i) t::isotropic_stiffness(K, G, D.data() + i * 36);
  }

  // A step's erosion-induced strain in substeps at the point's held total
  // strain, each at the stress ratio the last left: the point's own
  // relaxation (base's elastic stiffness D, frozen over the step), by Heun's
  // method (a held sample eroding 1% in one step ends within 3e-4 of an
  // independent integration: tests/test_suffosion.cpp). A substep changes
  // p' or q by at most a fiftieth of p' (on the onset curve below, up to
  // half of p' before its share); once p' falls below a
  // thousandth of its start the point is slack and the rest of the step's
  // erosion deforms nothing, as at no confinement. q is measured along the
  // step's deviator: a shear strain that relaxes q past zero leaves ratio 0.
  struct Relaxed {
    SuffosionLaw::Strain strain;
    t::Voigt tensor{};
    double eta = 0;  // the ratio the substeps leave
  };
  Relaxed relax(const double* s, const t::Voigt& dev, double q0, const double* D, double f, double df) const {
    constexpr double stress_change = 0.02, largest_change = 0.5, slack = 1e-3;
    constexpr int most_substeps = 1000;
    auto along = [&](const t::Voigt& v) {  // (3/2) v' : dev / q0, the change of q along dev
      return q0 > 0 ? 1.5 * t::double_contraction(t::deviator(v.data()).data(), dev.data()) / q0 : 0.0;
    };
    auto stress_of = [&](const t::Voigt& e) {  // D e, e a tensor (engineering shear for D)
      t::Voigt out{};
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) out[i] += D[i * 6 + j] * e[j] * (j < 3 ? 1.0 : 2.0);
      return out;
    };
    Relaxed out;
    t::Voigt sigma;
    std::copy(s, s + 6, sigma.begin());
    const double p0 = t::mean_stress(s);
    double done = f - df;
    auto ratio = [&](const t::Voigt& v) {  // eta of a stress (the cap where p' <= 0)
      const double p = t::mean_stress(v.data());
      return p > 0 ? std::min(std::max(0.0, along(v)) / p, law_.eta_max) : law_.eta_max;
    };
    // On the onset curve a substep takes a share of its strain: the next
    // erodes more, for the same change of stress (its full strain changing
    // the stress by at most half of p').
    double on_curve = 1;
    for (int k = 0; k < most_substeps && done < f; ++k) {
      const double p = t::mean_stress(sigma.data());
      if (!(p > slack * p0)) break;
      const double eta = out.eta = ratio(sigma);
      if (done < law_.onset(eta)) {  // nothing deforms, the stress stays, until f_er reaches the onset
        done = std::min(f, law_.onset(eta));
        continue;
      }
      // Stress change per unit of erosion at this ratio, to size the substep.
      const SuffosionLaw::Rates rate = law_.rates(eta);
      const t::Voigt unit = stress_of(strain_tensor({rate.volumetric, rate.shear}, dev, q0));
      const double change = std::max(std::abs(t::mean_stress(unit.data())), std::abs(along(unit)));
      const double step = std::min(f - done, stress_change * p / change * on_curve);
      // Heun: the strain at this ratio and at the ratio it would leave, averaged.
      const SuffosionLaw::Strain d0 = law_.of_step(eta, done + step, step);
      t::Voigt predicted = sigma;
      const t::Voigt relief0 = stress_of(strain_tensor(d0, dev, q0));
      for (int c = 0; c < 6; ++c) predicted[c] -= relief0[c];
      const double eta1 = ratio(predicted), onset1 = law_.onset(eta1);
      SuffosionLaw::Strain d;
      if (onset1 > done + step) {
        // The relaxation lowers eta past the onset curve within the substep:
        // the point takes only the share of the strain that leaves it on the
        // curve at the substep's end, onset(eta) = done + step (eta linear in
        // the share; bisection, the onset being steep near M_so), and so
        // follows the curve instead of overshooting past it.
        double lo = 0, hi = 1;
        for (int i = 0; i < 50; ++i) {
          const double share = 0.5 * (lo + hi);
          (law_.onset(eta + share * (eta1 - eta)) > done + step ? hi : lo) = share;
        }
        d = {lo * d0.volumetric, lo * d0.shear};
        out.eta = eta + lo * (eta1 - eta);
        on_curve = std::min(1 / std::max(lo, 1e-3), largest_change / stress_change);
      } else {
        const SuffosionLaw::Strain d1 = law_.of_step(eta1, done + step, step);
        d = {0.5 * (d0.volumetric + d1.volumetric), 0.5 * (d0.shear + d1.shear)};
        out.eta = eta1;
        on_curve = 1;
      }
      done += step;
      if (d.volumetric == 0 && d.shear == 0) continue;  // before the onset
      out.strain.volumetric += d.volumetric;
      out.strain.shear += d.shear;
      const t::Voigt e = strain_tensor(d, dev, q0), relief = stress_of(e);
      for (int c = 0; c < 6; ++c) out.tensor[c] += e[c], sigma[c] -= relief[c];
    }
    return out;
  }

  const suffuse::Phase* base_;
  SuffosionLaw law_;
  bool substeps_, implicit_;
  std::optional<double> e0_given_;
  std::string where_;
  suffuse::FieldId f_ = 0, df_ = 0, ev_ = 0, es_ = 0, onset_ = 0, e0_ = 0, base_e_ = 0;
  std::optional<suffuse::FieldId> e_, psi_;
  std::optional<suffuse::FieldId> eigenstrain_, eigenstrain_increment_;  // the core's, where it has them
  suffuse::FieldId volumetric_gradient_ = 0, shear_gradient_ = 0, shear_direction_ = 0;  // "implicit" only
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::Phase, Suffosion>(
      "phase/suffosion",
      "Erosion-induced deformation (DEM study of gap-graded soils) around a base skeleton given under \"base\"");
}
