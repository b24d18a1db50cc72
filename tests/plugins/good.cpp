// A plugin library as a third party would write it: two kinds in one library.
#include <suffuse/plugin.hpp>

namespace {

class ConstantDensity final : public suffuse::Phase {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("density").with_unit("kg/m^3").above(0).fallback(1000.0).doc("Mass density");
    return s;
  }
  explicit ConstantDensity(const suffuse::PluginArgs& a) : rho_(a.params.number("density")) {}
  double density() const override { return rho_; }
  double p_wave_modulus() const override { return 1.0; }
  void update_stress(const suffuse::StressBatch&) const override {}

 private:
  double rho_;
};

class NoErosion final : public suffuse::ErosionLaw {
 public:
  static suffuse::ParameterSchema schema() { return {}; }
  explicit NoErosion(const suffuse::PluginArgs&) {}
  void rate(const suffuse::ErosionBatch& b) const override {
    for (double& r : b.rate) r = 0;
  }
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::Phase, ConstantDensity>("phase/test_constant", "Test phase: no stress");
  registry.add<suffuse::ErosionLaw, NoErosion>("erosion/test_none", "Test erosion law: zero rate");
}
