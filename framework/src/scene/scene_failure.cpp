// When a quasi-static run counts its structure as failed, and stops there or
// hands over to an explicit run that follows the collapse
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
  s.number("collapse").with_unit("s").above(0).may_be_absent().doc(
      "Seconds of explicit dynamics that follow the failure: from the last equilibrium, at rest, without mass "
      "scaling or damping, the drag semi-implicit where the conductivity is low (docs/slope-stability.md, "
      "Collapse). Absent: the run stops at the failure");
  s.number("collapse_cfl").with_unit("-").above(0).at_most(1).fallback(defaults.collapse_cfl).doc(
      "The collapse's automatic time step: this times the cell size over the fastest wave speed, as /time/cfl");
  s.number("collapse_output_interval").with_unit("s").above(0).may_be_absent().doc(
      "Time between the collapse's frames and ledger rows (absent: a tenth of /failure/collapse); every output "
      "keeps its own interval before the failure");
  return s;
}

void read_failure(SceneReader& r, Scene& scene) {
  if (!r.root.contains("failure")) return;
  const std::string ptr = "/failure";
  Parameters f = validate_object(r.root["failure"], failure_schema(), ptr, "core (failure)", r.dim, r.diags);
  FailureSpec spec;
  if (f.has("factor_of_safety")) spec.factor_of_safety = f.number("factor_of_safety");
  spec.collapse = f.maybe_number("collapse");
  if (f.has("collapse_cfl")) spec.collapse_cfl = f.number("collapse_cfl");
  spec.collapse_output_interval = f.maybe_number("collapse_output_interval");
  for (const char* key : {"collapse_cfl", "collapse_output_interval"})
    if (!spec.collapse && r.root["failure"].contains(key))
      r.error(ptr + "/" + key, "a control of a collapse that does not follow",
              "/failure/collapse, the seconds of explicit dynamics after the failure", "no /failure/collapse",
              "core (failure)");
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
          "checkpoint at the time of failure, or hands over to an explicit run that follows the collapse "
          "(collapse; docs/slope-stability.md)",
          failure_schema, read_failure};
}

}  // namespace suffuse::detail
