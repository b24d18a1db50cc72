// The factor of safety over a run: when the shear strength reduction is
// made, and how finely (docs/slope-stability.md).
#include "scene/scene_reader.hpp"

namespace suffuse::detail {

namespace {

ParameterSchema factor_of_safety_schema() {
  const FactorOfSafetySpec defaults;
  ParameterSchema s;
  s.number("interval").with_unit("s").above(0).may_be_absent().doc(
      "Simulated time between factors of safety (each after the step that reaches a multiple of it; the first after "
      "the first step, the initial stresses being no equilibrium); absent: after the first step and at the end "
      "only. Each is written as a row of <scene>.factor_of_safety.csv");
  s.number("tolerance").with_unit("-").above(0).below(1).fallback(defaults.tolerance).doc(
      "The search stops when the factor is bracketed this finely: the largest factor that held and the smallest "
      "that did not differ by less");
  s.number("increment").with_unit("-").above(0).fallback(defaults.increment).doc(
      "The factor rises from 1 in these steps until a solve fails (then the bracket is halved)");
  s.number("max_factor").with_unit("-").above(1).fallback(defaults.max_factor).doc(
      "The factor is not raised beyond it: a state that holds there has a factor of safety of at least it");
  s.integer("max_iterations").at_least(1).fallback(defaults.max_iterations).doc(
      "Newton iterations after which a solve counts as failed: no equilibrium at that factor");
  return s;
}

void read_factor_of_safety(SceneReader& r, Scene& scene) {
  if (!r.root.contains("factor_of_safety")) return;
  const std::string ptr = "/factor_of_safety";
  Parameters f = validate_object(r.root["factor_of_safety"], factor_of_safety_schema(), ptr, "core (factor of safety)",
                                 r.dim, r.diags);
  FactorOfSafetySpec spec;
  spec.interval = f.maybe_number("interval");
  if (f.has("tolerance")) spec.tolerance = f.number("tolerance");
  if (f.has("increment")) spec.increment = f.number("increment");
  if (f.has("max_factor")) spec.max_factor = f.number("max_factor");
  if (f.has("max_iterations")) spec.max_iterations = static_cast<int>(f.integer("max_iterations"));
  if (scene.integration != TimeIntegration::quasi_static)
    r.error(ptr, "a strength reduction in an explicit run",
            "\"integration\": \"quasi_static\" in /time (a factor of safety is found from equilibria)",
            "integration explicit", "core (factor of safety)");
  scene.factor_of_safety = spec;
}

}  // namespace

SceneSection factor_of_safety_section() {
  return {"factor_of_safety", "factor_of_safety",
          "The factor of safety by shear strength reduction over a quasi-static run (docs/slope-stability.md)",
          factor_of_safety_schema, read_factor_of_safety};
}

}  // namespace suffuse::detail
