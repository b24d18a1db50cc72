// Erosion laws: n_e, the solid volume detached from the skeleton per unit
// volume and time [1/s], from the state of a batch of points. The core moves
// the mass, keeps f_c >= f_c_inf and counts everything (docs/erosion.md).
// Each law may be switched on by a hydraulic-gradient threshold i_cr.
#include <suffuse/plugin.hpp>

namespace {

void declare_common(suffuse::ParameterSchema& s) {
  s.number("critical_gradient").with_unit("-").at_least(0).fallback(0.0).doc(
      "Onset threshold i_cr: no erosion where the hydraulic gradient |i| = |q| / K is below it (0: always on)");
}

// Vardoulakis, Stavropoulou & Papanastasiou (1996), Transport in Porous Media
// 22:225: n_e = lambda (1 - n) c |q|. Erosion grows with the fines already in
// suspension, so it needs c > 0 somewhere to start.
class Vardoulakis final : public suffuse::ErosionLaw {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("lambda").with_unit("1/m").at_least(0).doc("Erosion coefficient lambda");
    declare_common(s);
    return s;
  }
  explicit Vardoulakis(const suffuse::PluginArgs& a)
      : lambda_(a.params.number("lambda")), i_cr_(a.params.number("critical_gradient")) {}
  void rate(const suffuse::ErosionBatch& b) const override {
    for (std::size_t p = 0; p < b.rate.size(); ++p)
      b.rate[p] = lambda_ * (1 - b.porosity[p]) * b.concentration[p] * b.darcy_flux[p];
    suffuse::switch_off_below_gradient(b, i_cr_);
  }

 private:
  double lambda_, i_cr_;
};

// Stavropoulou, Papanastasiou & Vardoulakis (1998), Int. J. Numer. Anal. Meth.
// Geomech. 22:749: n_e = lambda (1 - n) (c - c^2 / c_cr) |q|. Erosion stops at
// the critical concentration c_cr and turns into deposition above it.
class VardoulakisCritical final : public suffuse::ErosionLaw {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("lambda").with_unit("1/m").at_least(0).doc("Erosion coefficient lambda");
    s.number("critical_concentration").with_unit("-").above(0).at_most(1).doc(
        "Critical concentration c_cr: erosion below it, deposition above");
    declare_common(s);
    return s;
  }
  explicit VardoulakisCritical(const suffuse::PluginArgs& a)
      : lambda_(a.params.number("lambda")),
        c_cr_(a.params.number("critical_concentration")),
        i_cr_(a.params.number("critical_gradient")) {}
  void rate(const suffuse::ErosionBatch& b) const override {
    for (std::size_t p = 0; p < b.rate.size(); ++p) {
      const double c = b.concentration[p];
      b.rate[p] = lambda_ * (1 - b.porosity[p]) * (c - c * c / c_cr_) * b.darcy_flux[p];
    }
    suffuse::switch_off_below_gradient(b, i_cr_);
  }

 private:
  double lambda_, c_cr_, i_cr_;
};

// Fines-limited law of the four-constituent framework (Yang, Yin, Zhang,
// Jin & Sheng 2019, Computers and Geotechnics 115:103157):
// n_e = lambda_e (1 - n) (f_c - f_c_inf) |q|. Needs no fines in suspension,
// and stops by itself at the ultimate fines content.
class FinesLimited final : public suffuse::ErosionLaw {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("lambda").with_unit("1/m").at_least(0).doc("Erosion coefficient lambda_e");
    declare_common(s);
    return s;
  }
  explicit FinesLimited(const suffuse::PluginArgs& a)
      : lambda_(a.params.number("lambda")), i_cr_(a.params.number("critical_gradient")) {}
  void rate(const suffuse::ErosionBatch& b) const override {
    for (std::size_t p = 0; p < b.rate.size(); ++p)
      b.rate[p] = lambda_ * (1 - b.porosity[p]) * (b.fines_content[p] - b.ultimate_fines_content[p]) * b.darcy_flux[p];
    suffuse::switch_off_below_gradient(b, i_cr_);
  }

 private:
  double lambda_, i_cr_;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::ErosionLaw, Vardoulakis>(
      "erosion/vardoulakis", "Vardoulakis et al. (1996): n_e = lambda (1-n) c |q|");
  registry.add<suffuse::ErosionLaw, VardoulakisCritical>(
      "erosion/vardoulakis_ccr", "Stavropoulou et al. (1998): n_e = lambda (1-n) (c - c^2/c_cr) |q|");
  registry.add<suffuse::ErosionLaw, FinesLimited>(
      "erosion/fines_limited", "Yang et al. (2019): n_e = lambda_e (1-n) (f_c - f_c_inf) |q|");
}
