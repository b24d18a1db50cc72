// phase/eroding_elastic: a coupled-phase plugin for suffuse, to copy. A
// linear elastic skeleton that softens as it loses its fines:
//
//   E(f_er) = E_0 max(r, 1 - a f_er)
//
// with f_er the point's eroded fraction (eroded mass over initial solid mass,
// from the erosion stage), a the softening rate and r the residual share of
// the stiffness. The skeleton is secant-elastic: its elastic strain is
// S(E) sigma, S the compliance. When erosion lowers E from E_old to E_new at
// a constant stress, the skeleton needs the extra strain
//
//   d eps* = (S(E_new) - S(E_old)) sigma = (E_old / E_new - 1) S(E_old) sigma
//
// to carry that stress. The phase writes it as an eigenstrain: the core
// removes it from the strain increment of the step, the stress relaxes, and
// the body deforms until it carries its load again: it settles.
//
// What a coupled phase does (docs/plugins.md has the whole guide):
// - required_fields() names the point fields of other parts it reads; a scene
//   that does not provide them is refused at validation, naming the field.
// - add_fields() looks them up by name, once, at set-up.
// - eigenstrain() and update_stress() get batches of points; they are called
//   from several threads at once on different batches: keep them const.
#include <algorithm>
#include <suffuse/plugin.hpp>
#include <suffuse/tensor.hpp>

namespace {

class ErodingElastic final : public suffuse::Phase {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("density").with_unit("kg/m^3").above(0).doc("Mass density (of the grains in a saturated body)");
    s.number("youngs_modulus").with_unit("Pa").above(0).doc("Young's modulus E_0 of the uneroded skeleton");
    s.number("poisson_ratio").with_unit("-").above(-1).below(0.5).fallback(0.0).doc("Poisson's ratio nu");
    s.number("softening").with_unit("-").at_least(0).fallback(5.0).doc(
        "Softening rate a: E = E_0 (1 - a f_er), so E halves when f_er = 1 / (2 a)");
    s.number("residual_stiffness").with_unit("-").above(0).at_most(1).fallback(0.2).doc(
        "Residual share r of E_0 that the skeleton keeps however much it loses");
    return s;
  }

  // Read by the core before anything is built: a scene without erosion has
  // no eroded fraction, and is refused.
  static std::vector<std::string> required_fields(const suffuse::Parameters&, int) {
    return {suffuse::coupling::eroded_fraction, suffuse::coupling::eroded_fraction_increment};
  }

  explicit ErodingElastic(const suffuse::PluginArgs& args)
      : rho_(args.params.number("density")),
        E0_(args.params.number("youngs_modulus")),
        nu_(args.params.number("poisson_ratio")),
        a_(args.params.number("softening")),
        r_(args.params.number("residual_stiffness")) {}

  double density() const override { return rho_; }
  double p_wave_modulus() const override { return E0_ * (1 - nu_) / ((1 + nu_) * (1 - 2 * nu_)); }

  void add_fields(suffuse::PointSet& points) override {
    eroded_ = points.id(suffuse::coupling::eroded_fraction);
    eroded_increment_ = points.id(suffuse::coupling::eroded_fraction_increment);
  }

  bool writes_eigenstrain() const override { return true; }

  void eigenstrain(const suffuse::StressBatch& b, std::span<double> increment) const override {
    const double* f = b.points.data(eroded_);
    const double* df = b.points.data(eroded_increment_);
    const double* stress = b.points.data(b.points.core().stress);
    for (std::size_t p = b.range.begin; p < b.range.end; ++p) {
      double* e = increment.data() + (p - b.range.begin) * 6;
      const double E_old = stiffness(f[p] - df[p]), E_new = stiffness(f[p]);
      const double factor = E_old / E_new - 1;
      // S(E_old) sigma = ((1 + nu) sigma - nu tr(sigma) I) / E_old
      const double* s = stress + p * 6;
      const double tr = suffuse::tensor::trace(s);
      for (int c = 0; c < 6; ++c) e[c] = factor * ((1 + nu_) * s[c] - (c < 3 ? nu_ * tr : 0.0)) / E_old;
    }
  }

  void update_stress(const suffuse::StressBatch& b) const override {
    if (b.points.dim() == 2)
      update<2>(b);
    else
      update<3>(b);
  }

 private:
  template <int D>
  void update(const suffuse::StressBatch& b) const {
    const double* f = b.points.data(eroded_);
    double* stress = b.points.data(b.points.core().stress);
    // The strain increment of each point without the eigenstrain, and the spin.
    const suffuse::StepIncrements<D> increments(b);
    for (std::size_t p = b.range.begin; p < b.range.end; ++p) {
      const double E = stiffness(f[p]);
      const double G = E / (2 * (1 + nu_)), lambda = E * nu_ / ((1 + nu_) * (1 - 2 * nu_));
      const auto [d, w] = increments(p);
      double* s6 = stress + p * 6;
      // Hooke's law with the Jaumann rate (a rigid rotation creates no stress).
      const suffuse::tensor::Matrix next =
          suffuse::tensor::jaumann_elastic_increment(suffuse::tensor::to_matrix(s6), d, w, G, lambda);
      suffuse::tensor::store(next, s6);
    }
  }

  // Deposition can make the net eroded fraction negative: the skeleton never
  // gets stiffer than E_0 (which also set the time step).
  double stiffness(double eroded_fraction) const {
    return E0_ * std::max(r_, 1 - a_ * std::max(0.0, eroded_fraction));
  }

  double rho_, E0_, nu_, a_, r_;
  suffuse::FieldId eroded_ = 0, eroded_increment_ = 0;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::Phase, ErodingElastic>(
      "phase/eroding_elastic", "Linear elastic skeleton whose stiffness falls with its eroded fraction");
}
