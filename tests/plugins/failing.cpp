// A phase that fails on purpose, for the tests of how a run reports a
// failing plugin: it throws, or returns a stress that is not finite.
#include <limits>
#include <stdexcept>
#include <suffuse/plugin.hpp>

namespace {

class FailingPhase final : public suffuse::Phase {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("density").with_unit("kg/m^3").above(0).fallback(1000.0).doc("Mass density");
    s.choice("failure", {"throw", "nan"}).doc("throw: an exception; nan: a stress that is not finite at the last point");
    return s;
  }
  explicit FailingPhase(const suffuse::PluginArgs& a)
      : rho_(a.params.number("density")), throws_(a.params.string("failure") == "throw") {}
  double density() const override { return rho_; }
  double p_wave_modulus() const override { return 1e6; }
  void update_stress(const suffuse::StressBatch& b) const override {
    if (throws_) throw std::runtime_error("the test phase fails");
    if (b.range.size() > 0)
      b.points.data(b.points.core().stress)[(b.range.end - 1) * 6 + 1] = std::numeric_limits<double>::quiet_NaN();
  }

 private:
  double rho_;
  bool throws_;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::Phase, FailingPhase>("phase/test_failing", "Test phase: throws or returns NaN");
}
