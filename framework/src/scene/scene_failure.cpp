// When a quasi-static run counts its structure as failed, and stops there
// (docs/slope-stability.md, Failure).
#include "scene/scene_reader.hpp"

namespace suffuse::detail {

namespace {

ParameterSchema failure_schema() {
  const FailureSpec defaults;
  ParameterSchema s;
  s.number("factor_of_safety").with_unit("-").above(0).fallback(defaults.factor_of_safety).doc(
      "A factor of safety below it (/factor_of_safety's evaluations) is a failure; a step without equilibrium, "
      "even halved, is one whatever this is");
  return s;
}

void read_failure(SceneReader& r, Scene& scene) {
  if (!r.root.contains("failure")) return;
  const std::string ptr = "/failure";
  Parameters f = validate_object(r.root["failure"], failure_schema(), ptr, "core (failure)", r.dim, r.diags);
  FailureSpec spec;
  if (f.has("factor_of_safety")) spec.factor_of_safety = f.number("factor_of_safety");
  if (scene.integration != TimeIntegration::quasi_static)
    r.error(ptr, "a failure criterion in an explicit run",
            "\"integration\": \"quasi_static\" in /time (a failure is an equilibrium lost, or a factor of safety "
            "below the limit; an explicit run follows a collapse instead)",
            "integration explicit", "core (failure)");
  scene.failure = spec;
}

}  // namespace

SceneSection failure_section() {
  return {"failure", "failure",
          "When a quasi-static run counts its structure as failed: it then stops, with every output and a "
          "checkpoint at the time of failure (docs/slope-stability.md)",
          failure_schema, read_failure};
}

}  // namespace suffuse::detail
