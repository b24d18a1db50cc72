// phase/test_swelling: linear elastic (nu = 0) with a constant in-plane
// eigenstrain rate, for the core's eigenstrain tests.
#include <suffuse/plugin.hpp>

namespace {

class Swelling final : public suffuse::Phase {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("density").with_unit("kg/m^3").above(0).doc("Mass density");
    s.number("youngs_modulus").with_unit("Pa").above(0).doc("Young's modulus, Poisson's ratio 0");
    s.number("rate").with_unit("1/s").doc("Eigenstrain rate of the xx and yy components");
    return s;
  }
  explicit Swelling(const suffuse::PluginArgs& a)
      : rho_(a.params.number("density")), E_(a.params.number("youngs_modulus")), rate_(a.params.number("rate")) {}
  double density() const override { return rho_; }
  double p_wave_modulus() const override { return E_; }
  bool writes_eigenstrain() const override { return true; }
  void eigenstrain(const suffuse::StressBatch& b, std::span<double> increment) const override {
    for (std::size_t k = 0; k < b.range.size(); ++k)
      for (int c = 0; c < 6; ++c) increment[k * 6 + c] = c < 2 ? rate_ * b.dt : 0.0;
  }
  void update_stress(const suffuse::StressBatch& b) const override {
    double* stress = b.points.data(b.points.core().stress);
    for (std::size_t p = b.range.begin; p < b.range.end; ++p) {
      const auto inc = suffuse::step_increment(b, p);
      for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j) stress[p * 6 + suffuse::tensor::voigt_index(i, j)] += E_ * inc.strain[i][j];
    }
  }

 private:
  double rho_, E_, rate_;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::Phase, Swelling>("phase/test_swelling", "Elastic with a constant eigenstrain rate (tests)");
}
