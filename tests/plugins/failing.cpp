// Plugins that fail on purpose, for the tests of how a run reports a
// failing plugin: a phase that throws or returns a stress that is not
// finite; an erosion law, a permeability law and a boundary condition that
// throw during a step.
#include <limits>
#include <stdexcept>
#include <string>
#include <suffuse/boundary_condition.hpp>
#include <suffuse/erosion_law.hpp>
#include <suffuse/liquid.hpp>
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
      // A negative NaN, as arithmetic makes them: the run must not report "-nan".
      b.points.data(b.points.core().stress)[(b.range.end - 1) * 6 + 1] = -std::numeric_limits<double>::quiet_NaN();
  }

 private:
  double rho_;
  bool throws_;
};

class FailingErosionLaw final : public suffuse::ErosionLaw {
 public:
  static suffuse::ParameterSchema schema() { return {}; }
  explicit FailingErosionLaw(const suffuse::PluginArgs&) {}
  void rate(const suffuse::ErosionBatch&) const override { throw std::runtime_error("the test erosion law fails"); }
};

// Kozeny-Carman's K0 until the porosity rises above a limit, then a throw.
class FailingPermeability final : public suffuse::PermeabilityLaw {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("hydraulic_conductivity").with_unit("m/s").above(0).doc("K, constant");
    s.number("fail_above_porosity").with_unit("-").above(0).doc("throws once a porosity of the batch passes it");
    return s;
  }
  explicit FailingPermeability(const suffuse::PluginArgs& a)
      : K_(a.params.number("hydraulic_conductivity")), limit_(a.params.number("fail_above_porosity")) {}
  void conductivity(std::span<const double> n, std::span<double> K) const override {
    for (std::size_t p = 0; p < n.size(); ++p) {
      if (n[p] > limit_) throw std::runtime_error("the test permeability law fails at porosity " + std::to_string(n[p]));
      K[p] = K_;
    }
  }

 private:
  double K_, limit_;
};

class FailingCondition final : public suffuse::BoundaryCondition {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("fail_at").with_unit("s").at_least(0).doc("throws in apply_forces from this time on");
    return s;
  }
  explicit FailingCondition(const suffuse::PluginArgs& a) : fail_at_(a.params.number("fail_at")) {}
  void setup(const suffuse::GridGeometry&) override {}
  void apply_forces(const suffuse::GridGeometry&, suffuse::NodeState&, double time) const override {
    if (time >= fail_at_) throw std::runtime_error("the test condition fails");
  }

 private:
  double fail_at_;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::Phase, FailingPhase>("phase/test_failing", "Test phase: throws or returns NaN");
  registry.add<suffuse::ErosionLaw, FailingErosionLaw>("erosion/test_failing", "Test erosion law: throws");
  registry.add<suffuse::PermeabilityLaw, FailingPermeability>("permeability/test_failing",
                                                              "Test permeability law: throws above a porosity");
  registry.add<suffuse::BoundaryCondition, FailingCondition>("bc/test_failing", "Test condition: throws from a time on");
}
