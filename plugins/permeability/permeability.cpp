// Permeability laws: hydraulic conductivity K of a soil skeleton as a function
// of its porosity n. K is defined with the standard gravity 9.81 m/s^2 and
// the pore liquid's density and viscosity (K = k rho_L g / mu).
#include <suffuse/plugin.hpp>

namespace {

class ConstantPermeability final : public suffuse::PermeabilityLaw {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("hydraulic_conductivity").with_unit("m/s").above(0).doc("Hydraulic conductivity K");
    return s;
  }
  explicit ConstantPermeability(const suffuse::PluginArgs& a) : K_(a.params.number("hydraulic_conductivity")) {}
  void conductivity(std::span<const double>, std::span<double> out) const override {
    for (double& k : out) k = K_;
  }

 private:
  double K_;
};

// Kozeny-Carman: K(n) = K_0 [n^3 / (1-n)^2] [(1-n_0)^2 / n_0^3].
class KozenyCarman final : public suffuse::PermeabilityLaw {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("hydraulic_conductivity").with_unit("m/s").above(0).doc("Hydraulic conductivity K_0 at the reference porosity");
    s.number("reference_porosity").with_unit("-").above(0).below(1).doc("Porosity n_0 at which K = K_0");
    return s;
  }
  explicit KozenyCarman(const suffuse::PluginArgs& a) {
    const double n0 = a.params.number("reference_porosity");
    scale_ = a.params.number("hydraulic_conductivity") * (1 - n0) * (1 - n0) / (n0 * n0 * n0);
  }
  void conductivity(std::span<const double> porosity, std::span<double> out) const override {
    for (std::size_t i = 0; i < out.size(); ++i) {
      const double n = porosity[i];
      out[i] = scale_ * n * n * n / ((1 - n) * (1 - n));
    }
  }

 private:
  double scale_;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::PermeabilityLaw, ConstantPermeability>("permeability/constant",
                                                               "Constant hydraulic conductivity");
  registry.add<suffuse::PermeabilityLaw, KozenyCarman>(
      "permeability/kozeny_carman", "Kozeny-Carman: K = K_0 n^3/(1-n)^2 (1-n_0)^2/n_0^3");
}
