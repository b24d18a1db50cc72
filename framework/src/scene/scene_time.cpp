// Time control: end time, time step, mass scaling, checkpoints.
#include "scene/scene_reader.hpp"

namespace suffuse::detail {

namespace {

ParameterSchema time_schema() {
  ParameterSchema s;
  s.number("end").with_unit("s").above(0).doc("Simulation end time");
  s.choice("integration", {"explicit", "quasi_static"}).fallback(std::string("explicit")).doc(
      "explicit: dynamics, steps bounded by the wave speeds (MUSL); quasi_static: a sequence of equilibria "
      "(implicit u-p consolidation, no inertia), steps bounded by the erosion and consolidation "
      "(docs/time-integration.md)");
  s.number("dt").with_unit("s").above(0).may_be_absent().doc(
      "Explicit: a fixed time step (absent: automatic, cfl * h / max wave speed). Quasi-static: the first step "
      "(required), after which steps adapt up to max_dt");
  s.number("max_dt").with_unit("s").above(0).may_be_absent().doc(
      "Quasi-static only: the largest step (absent: dt, a fixed step unless the erosion tolerance cuts it)");
  s.number("growth").with_unit("-").at_least(1).fallback(1.5).doc(
      "Quasi-static only: a step is at most this factor times the previous one");
  s.number("eroded_fraction_tolerance").with_unit("-").above(0).at_most(1).fallback(0.05).doc(
      "Quasi-static only: the largest change of any point's eroded fraction over one step; a step that erodes "
      "more makes the next one shorter in proportion");
  s.number("transport_courant").with_unit("-").above(0).at_most(0.25).fallback(0.2).doc(
      "Quasi-static only: Courant number q dt / (n h) of the erosion and transport substeps within a step (at "
      "most 0.25: above it the transport's limiter holds back what a node sends)");
  s.number("steady_transport_tolerance").with_unit("-").at_least(0).below(1).fallback(1e-3).doc(
      "Quasi-static only: the transport is steady when a substep erodes nothing and the substeps left, changing "
      "the composition as much as it did, would change no node's fines share of the liquid by more than this "
      "fraction of the largest; the rest of the step is then one backward-Euler step (upwind: stable for any "
      "step, positive, conservative) instead of the substeps. 0: substeps to the end of every step");
  s.number("newton_tolerance").with_unit("-").above(0).below(1).fallback(1e-8).doc(
      "Quasi-static only: equilibrium is reached when the out-of-balance force is below this fraction of the "
      "forces acting");
  s.integer("max_iterations").at_least(1).fallback(25).doc(
      "Quasi-static only: iterations per step before the step is halved and tried again");
  s.number("creep").with_unit("-").at_least(0).below(1).fallback(1e-4).doc(
      "Quasi-static only: where points have no stiffness (a cohesionless layer separated by seepage: heave, "
      "fluidisation), a stiffness holding their nodes to their place at the start of the step, this fraction of "
      "the skeleton's; such a layer creeps from step to step instead of the step failing (0: none)");
  s.boolean("reuse_factors").fallback(true).doc(
      "Quasi-static only: the Newton iterations after a step's first solve their linear system "
      "by GMRES preconditioned by the factors of the step's last factorised matrix, and factorise only where "
      "GMRES does not converge in 30 iterations to 1e-6 or leaves a true residual above 1e-5 of the right-hand "
      "side (the same equilibria within the Newton tolerance, much less work where the tangent changes); false: "
      "every iteration factorises its own matrix. On many processes the same through PETSc: GMRES preconditioned "
      "by the preconditioner its solver last set up. A strength reduction's solves (/factor_of_safety) factorise every "
      "iteration");
  s.choice("linear_solver", {"auto", "mumps", "eigen"}).fallback(std::string("auto")).doc(
      "Quasi-static only: the direct solver of each step's linear systems on one process. mumps: MUMPS through "
      "PETSc (multifrontal LU; the flood levee's factorisations about three times faster); eigen: "
      "Eigen's SparseLU (COLAMD) or SimplicialLDLT; auto: mumps on grids of " +
      std::to_string(mumps_from_grid_nodes) +
      " nodes or more where this build has PETSc, eigen otherwise (on smaller grids PETSc's set-up of each solve "
      "costs more than it saves). "
      "Both reach the same equilibria within the Newton tolerance. On many processes always PETSc's");
  s.boolean("inertia").fallback(false).doc(
      "Quasi-static only: the mixture's inertia joins each step's balance (backward Euler: the nodal mass times "
      "(du - dt v) / dt^2, v the velocity at the step's start), which makes it implicit dynamics. Negligible in "
      "long steps; where the skeleton loses its equilibrium (a heave, a collapse) it lets the soil accelerate "
      "instead of the steps shrinking without end. false: equilibria only");
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

// The integration and the keys that belong to one of them only.
void read_integration(SceneReader& r, const Parameters& t, Scene& scene) {
  const bool quasi_static = t.has("integration") && t.string("integration") == "quasi_static";
  const char* qs_keys[] = {"max_dt", "growth", "eroded_fraction_tolerance", "transport_courant",
                           "steady_transport_tolerance", "newton_tolerance",
                           "max_iterations", "creep", "reuse_factors", "inertia", "linear_solver"};
  if (!quasi_static) {
    for (const char* key : qs_keys)
      if (r.root["time"].contains(key))
        r.error(std::string("/time/") + key, "a quasi-static step control in an explicit run",
                "\"integration\": \"quasi_static\" or no " + std::string(key), "integration explicit", "core (time)");
    return;
  }
  scene.integration = TimeIntegration::quasi_static;
  QuasiStaticControls& q = scene.quasi_static;
  if (!t.has("dt"))
    r.error("/time/dt", "no first step for a quasi-static run", "a time step in s (e.g. a hundredth of /time/end)",
            "none", "core (time)");
  if (t.has("max_dt")) q.max_dt = t.number("max_dt");
  if (t.has("dt") && t.has("max_dt") && q.max_dt < t.number("dt"))
    r.error("/time/max_dt", "a largest step below the first", "max_dt >= dt = " + format(t.number("dt")),
            format(q.max_dt), "core (time)");
  if (t.has("growth")) q.growth = t.number("growth");
  if (t.has("eroded_fraction_tolerance")) q.eroded_fraction_tolerance = t.number("eroded_fraction_tolerance");
  if (t.has("transport_courant")) q.transport_courant = t.number("transport_courant");
  if (t.has("steady_transport_tolerance")) q.steady_transport_tolerance = t.number("steady_transport_tolerance");
  if (t.has("newton_tolerance")) q.newton_tolerance = t.number("newton_tolerance");
  if (t.has("max_iterations")) q.max_iterations = static_cast<int>(t.integer("max_iterations"));
  if (t.has("creep")) q.creep = t.number("creep");
  if (t.has("reuse_factors")) q.reuse_factors = t.boolean("reuse_factors");
  if (t.has("inertia")) q.inertia = t.boolean("inertia");
  // SUFFUSE_PETSC: the core's build has the PETSc module (framework/CMakeLists.txt).
#ifdef SUFFUSE_PETSC
  constexpr bool with_petsc = true;
#else
  constexpr bool with_petsc = false;
#endif
  const std::string solver = t.has("linear_solver") ? t.string("linear_solver") : "auto";
  if (solver == "mumps" && !with_petsc)
    r.error("/time/linear_solver", "a solver this build does not have",
            "\"eigen\" or \"auto\" (MUMPS comes with PETSc: install libpetsc-real-dev and rebuild; docs/parallel.md)",
            "\"mumps\"", "core (time)");
  q.linear_solver = solver == "eigen" ? LinearSolver::eigen
                    : solver == "mumps" ? LinearSolver::mumps
                                        : LinearSolver::automatic;
  // What only dynamics has would be silently ignored: refused instead.
  for (const char* key : {"cfl", "mass_scaling", "dt_above_stable"})
    if (r.root["time"].contains(key))
      r.error(std::string("/time/") + key, "a control of explicit dynamics in a quasi-static run",
              "no " + std::string(key) + " (a quasi-static run has no inertia and no stability limit)", "present",
              "core (time)");
  if (scene.damping != 0)
    r.error("/damping", "damping in a quasi-static run", "no damping (a quasi-static run has no inertia to damp)",
            format(scene.damping), "core (time)");
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
  read_integration(r, t, scene);
}

}  // namespace

SceneSection time_section() { return {"time", "time", "Time control", time_schema, read_time}; }

}  // namespace suffuse::detail
