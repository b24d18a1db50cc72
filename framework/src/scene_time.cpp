// Time control: end time, time step, mass scaling, checkpoints.
#include "scene_reader.hpp"

namespace suffuse::detail {

namespace {

ParameterSchema time_schema() {
  ParameterSchema s;
  s.number("end").with_unit("s").above(0).doc("Simulation end time");
  s.number("dt").with_unit("s").above(0).may_be_absent().doc(
      "Fixed time step; absent: automatic, cfl * h / max wave speed");
  s.number("cfl").with_unit("-").above(0).at_most(1).fallback(0.5).doc(
      "Courant factor of the automatic time step");
  s.number("mass_scaling").with_unit("-").at_least(1).fallback(1.0).doc(
      "Multiplies every inertia (not the weight) for quasi-static runs: the automatic step grows by its square "
      "root; dynamics are no longer physical. Printed in the run log and stored in <name>.run.json");
  s.boolean("dt_above_stable").fallback(false).doc(
      "Accept a fixed dt above the stable time step (refused otherwise): only for scenes where nothing moves, "
      "such as an erosion law tested in a closed box. A run that blows up is still stopped, naming the point");
  s.number("checkpoint_interval").with_unit("s").above(0).may_be_absent().doc(
      "Simulated time between checkpoints (<output>/<name>.checkpoint, replaced each time; `suffuse run "
      "--checkpoint-every` overrides it); absent: none during the run");
  s.boolean("checkpoint_at_end").fallback(true).doc(
      "Write a checkpoint at the end time too, so that the run can be extended (raise /time/end and run with "
      "--restart)");
  return s;
}

void read_time(SceneReader& r, Scene& scene) {
  if (!r.require("time")) return;
  Parameters t = validate_object(r.root["time"], time_schema(), "/time", "core (time)",
                                         r.dim, r.diags);
  if (t.has("end")) scene.end_time = t.number("end");
  scene.dt = t.maybe_number("dt");
  if (t.has("cfl")) scene.cfl = t.number("cfl");
  if (t.has("mass_scaling")) scene.mass_scaling = t.number("mass_scaling");
  scene.checkpoint_interval = t.maybe_number("checkpoint_interval");
  if (t.has("dt_above_stable")) scene.dt_above_stable = t.boolean("dt_above_stable");
  if (t.has("checkpoint_at_end")) scene.checkpoint_at_end = t.boolean("checkpoint_at_end");
}

}  // namespace

SceneSection time_section() { return {"time", "time", "Time control", time_schema, read_time}; }

}  // namespace suffuse::detail
