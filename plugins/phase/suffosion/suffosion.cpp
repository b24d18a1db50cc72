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
// d eps_s = A beta eta (1 - x^xi) / (M_c^2 (1 - x^2)) d f_er with x = eta/M_c:
// both factors change sign at x = 1, where D = 0, so the ratio is taken in
// that form, with its limit xi/2 where |1 - x^2| < 1e-8: no division by
// zero, and d eps_s is finite and positive on both sides of M_c.
//
// The void ratio follows the fines lost: e = (1 + e_0) exp(-eps_v) / (1 -
// f_er) - 1, eps_v the skeleton's accumulated volumetric strain (the study's
// e = (e_0 + f_er)/(1 - f_er) - eps_v (e_0 + 1)/(1 - f_er) to first order in
// eps_v, and without erosion the exact void ratio a critical-state base
// integrates). A base that tracks "void_ratio" (and "state_parameter") has
// them set to it; its hardening counts the eigenstrain (Modified Cam-Clay:
// p_c follows the erosion-induced compaction along its lines).
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <suffuse/error.hpp>
#include <suffuse/plugin.hpp>
#include <suffuse/tensor.hpp>

namespace {

namespace t = suffuse::tensor;

// The study's relations, parameters parsed once.
struct SuffosionLaw {
  double M_so, f_so0, M_c, A, xi, beta, eta_max;

  // Eroded fraction at which erosion starts to deform the skeleton.
  double onset(double eta) const {
    const double r = eta / M_so;
    return r < 1 ? f_so0 * std::sqrt(1 - r * r) : 0.0;
  }
  // d eps_v / d f_er after onset (compression positive).
  double volumetric_rate(double eta) const { return -A * std::expm1(xi * std::log(eta / M_c)); }
  // d eps_s / d f_er after onset: volumetric_rate / D, finite at D = 0.
  double shear_rate(double eta) const {
    if (eta <= 0) return 0.0;
    const double x = eta / M_c, one_minus_x2 = (1 - x) * (1 + x);
    const double ratio = std::abs(one_minus_x2) < 1e-8 ? xi / 2 : -std::expm1(xi * std::log(x)) / one_minus_x2;
    return A * beta * eta * ratio / (M_c * M_c);
  }
};

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
  void eigenstrain(const suffuse::StressBatch& b, std::span<double> increment) const override {
    if (base_->writes_eigenstrain()) base_->eigenstrain(b, increment);
    suffuse::PointSet& pts = b.points;
    const double* stress = pts.data(pts.core().stress);
    const double* f = pts.data(f_);
    const double* df = pts.data(df_);
    double* ev = pts.data(ev_);
    double* es = pts.data(es_);
    double* onset = pts.data(onset_);
    for (std::size_t p = b.range.begin; p < b.range.end; ++p) {
      const double* s = stress + p * 6;
      const double mean = t::mean_stress(s), q = t::deviatoric_stress(s);
      if (!(mean > 0)) {  // no confinement: no skeleton stress to deform under
        onset[p] = 1.0;
        continue;
      }
      const double eta = std::min(q / mean, law_.eta_max);
      const double f_so = onset[p] = law_.onset(eta);
      // The part of this step's erosion beyond the onset (deposition deforms nothing).
      const double active = std::max(0.0, f[p] - std::max(f[p] - df[p], f_so));
      if (active <= 0) continue;
      const double d_ev = law_.volumetric_rate(eta) * active, d_es = law_.shear_rate(eta) * active;
      ev[p] += d_ev;
      es[p] += d_es;
      // Tension positive: -d_ev/3 I, and d_es along the deviator (3/2 s/q has eps_s 1).
      const t::Voigt dev = t::deviator(s);
      double* inc = increment.data() + (p - b.range.begin) * 6;
      for (int c = 0; c < 6; ++c) inc[c] += (c < 3 ? -d_ev / 3 : 0.0) + (q > 0 ? 1.5 * d_es * dev[c] / q : 0.0);
    }
  }

  // The base's: the erosion-induced strain is imposed, not a stiffness.
  bool tangent(const suffuse::StressBatch& b, std::span<double> stiffness) const override {
    return base_->tangent(b, stiffness);
  }
  void update_stress(const suffuse::StressBatch& b) const override {
    base_->update_stress(b);
    if (!e_) return;
    suffuse::PointSet& pts = b.points;
    const double* strain = pts.data(pts.core().strain);
    const double* f = pts.data(f_);
    const double* e0 = pts.data(e0_);
    const double* base_e = pts.data(base_e_);
    double* e = pts.data(*e_);
    double* psi = psi_ ? pts.data(*psi_) : nullptr;
    for (std::size_t p = b.range.begin; p < b.range.end; ++p) {
      if (!(e0[p] > 0)) continue;  // no void ratio tracked here
      if (!(f[p] < 1))
        throw suffuse::Error(where_ + " (phase/suffosion): material point " + std::to_string(p) +
                             " has lost all its solid (eroded fraction " + std::to_string(f[p]) + ")");
      // The void-ratio identity, with the accumulated volumetric strain.
      const double e_new = (1 + e0[p]) * std::exp(-t::volumetric_strain(strain + p * 6)) / (1 - f[p]) - 1;
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

  const suffuse::Phase* base_;
  SuffosionLaw law_;
  std::optional<double> e0_given_;
  std::string where_;
  suffuse::FieldId f_ = 0, df_ = 0, ev_ = 0, es_ = 0, onset_ = 0, e0_ = 0, base_e_ = 0;
  std::optional<suffuse::FieldId> e_, psi_;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::Phase, Suffosion>(
      "phase/suffosion",
      "Erosion-induced deformation (DEM study of gap-graded soils) around a base skeleton given under \"base\"");
}
