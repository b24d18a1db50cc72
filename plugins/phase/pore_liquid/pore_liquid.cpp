// phase/pore_liquid: the liquid that saturates a soil (water by default).
#include <suffuse/plugin.hpp>

namespace {

class PoreLiquid final : public suffuse::Liquid {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("density").with_unit("kg/m^3").above(0).fallback(1000.0).doc("Liquid density rho_L");
    s.number("bulk_modulus").with_unit("Pa").above(0).fallback(suffuse::water_bulk_modulus).doc(
        "Bulk modulus K_L (2.2e9 for water); a lower value gives a larger time step and is reported in the run log");
    s.number("viscosity").with_unit("Pa s").above(0).fallback(1.0e-3).doc("Dynamic viscosity mu");
    return s;
  }
  explicit PoreLiquid(const suffuse::PluginArgs& a)
      : rho_(a.params.number("density")), K_(a.params.number("bulk_modulus")), mu_(a.params.number("viscosity")) {}
  double density() const override { return rho_; }
  double bulk_modulus() const override { return K_; }
  double viscosity() const override { return mu_; }

 private:
  double rho_, K_, mu_;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::Liquid, PoreLiquid>("phase/pore_liquid",
                                            "Pore liquid: density, bulk modulus and viscosity (water by default)");
}
