#pragma once
// A phase: the constitutive behaviour of one material (the soil skeleton).
//
// What a phase gets: the points of its material, in batches (one thread's
// share of a material's range), with every per-point field of the run: the
// core's (stress, velocity_gradient, ...), its own state fields (registered
// in add_fields) and the fields other parts own, found by name in add_fields.
// The coupling fields of a saturated, eroding run are listed below; a phase
// that reads one declares it in its static required_fields(), and a scene
// that does not provide it is refused at validation with the field's name.
//
// What a phase returns: the new stress of each point of the batch, its own
// state, and optionally an eigenstrain increment (an inelastic strain the
// phase imposes, e.g. the compaction of an eroding skeleton). The core
// records the eigenstrain (field "eigenstrain") and removes it from the strain
// increment of the step before the stress update: step_increment() and
// StepIncrements below return sym(L) dt minus the eigenstrain, so a base model wrapped by
// another phase responds to the elastic part only.
#include <cstddef>
#include <span>

#include "suffuse/points.hpp"
#include "suffuse/tensor.hpp"

namespace suffuse {

// A contiguous range of points made of one material.
struct PointRange {
  std::size_t begin = 0;
  std::size_t end = 0;
  std::size_t size() const { return end - begin; }
};

// Per-point fields other parts provide to phases, by name (scalars, [-]).
// Saturated runs: "porosity", "porosity_increment". Runs that track fines
// (a material erodes, a body holds fines or an inlet brings them):
// "fines_content", "fines_content_increment", "eroded_fraction" (eroded
// mass over initial solid mass, f_er) and "eroded_fraction_increment".
// Increments are over the current step: deformation and erosion of this step
// happen before the stress update. The eroded fraction is net of deposition,
// so it can be negative where a point gained more fines than it lost.
namespace coupling {
inline constexpr const char* porosity = "porosity";
inline constexpr const char* porosity_increment = "porosity_increment";
inline constexpr const char* fines_content = "fines_content";
inline constexpr const char* fines_content_increment = "fines_content_increment";
inline constexpr const char* eroded_fraction = "eroded_fraction";
inline constexpr const char* eroded_fraction_increment = "eroded_fraction_increment";
// Written by a phase whose grains separate (phase/linear_elastic's tension
// cut-off): in how many principal directions a point has no stiffness (0 to
// 3). Quasi-static runs hold the nodes of such points with the creep term
// (/time/creep), as they hold those of points with no stiffness at all.
inline constexpr const char* separated_directions = "separated_directions";
}  // namespace coupling

// One batch of a phase's points for one step.
struct StressBatch {
  PointSet& points;   // every field; index it with p in [range.begin, range.end)
  PointRange range;
  double dt;
  // The eigenstrain increment of this step, 6 per point of the batch
  // (point p at (p - range.begin) * 6), as the phase's eigenstrain() wrote
  // it; empty when the phase writes none.
  std::span<const double> eigenstrain;
  // The factor F of a strength reduction (docs/slope-stability.md): a phase
  // that reduces_strength() divides its strength by it in update_stress and
  // tangent (Mohr-Coulomb: c / F and tan(phi) / F). 1 in every step of a run.
  double strength_reduction = 1.0;
  // update_stress only: false where the caller will not ask for tangent()
  // of this update (explicit steps, element tests); true where it may (a
  // quasi-static iterate), and by default, so that a caller that forgets it
  // loses time, not the tangent. A phase whose tangent needs more than its
  // update computes that only when true (phase/suffosion "implicit":
  // twelve more local solves per eroding point). Since plugin ABI 21.1.
  bool tangent_follows = true;
};

// Strain and spin increments of a point over the step, 3x3 (zero out of
// plane in 2D): d = sym(L) dt - eigenstrain, w = skew(L) dt, L the core's
// "velocity_gradient". Every phase reads its strain through these, so an
// eigenstrain is applied the same way by every model.
struct StepIncrement {
  tensor::Matrix strain{}, spin{};
};

// The increments of a batch's points, for a loop over them: built once per
// batch, with the dimension known at compile time.
template <int D>
class StepIncrements {
 public:
  explicit StepIncrements(const StressBatch& b)
      : L_(b.points.data(b.points.core().velocity_gradient)),
        dt_(b.dt),
        eigenstrain_(b.eigenstrain.empty() ? nullptr : b.eigenstrain.data()),
        first_(b.range.begin) {}
  StepIncrement operator()(std::size_t p) const {
    const double* L = L_ + p * D * D;
    StepIncrement inc;
    for (int i = 0; i < D; ++i)
      for (int j = 0; j < D; ++j) {
        inc.strain[i][j] = 0.5 * (L[i * D + j] + L[j * D + i]) * dt_;
        inc.spin[i][j] = 0.5 * (L[i * D + j] - L[j * D + i]) * dt_;
      }
    if (eigenstrain_) {
      const double* e = eigenstrain_ + (p - first_) * 6;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) inc.strain[i][j] -= e[tensor::voigt_index(i, j)];
    }
    return inc;
  }

 private:
  const double* L_;
  double dt_;
  const double* eigenstrain_;
  std::size_t first_;
};

// The same for one point, the dimension read at run time.
inline StepIncrement step_increment(const StressBatch& b, std::size_t p) {
  return b.points.dim() == 2 ? StepIncrements<2>(b)(p) : StepIncrements<3>(b)(p);
}

class Phase {
 public:
  virtual ~Phase() = default;

  // Mass density of the material [kg/m^3], used to give points their mass
  // (of the grains, in a saturated body).
  virtual double density() const = 0;
  // Constrained (P-wave) modulus [Pa] at the initial state; sqrt(M/rho) is
  // the wave speed that bounds the explicit time step.
  virtual double p_wave_modulus() const = 0;

  // Called once at set-up, after every part of the core registered its
  // fields and before any point exists: register this phase's state fields
  // (PointSet::add_field) and look up the fields it reads (PointSet::id).
  virtual void add_fields(PointSet& points) { (void)points; }
  // Set the initial state of this material's points (after geometry, mass,
  // initial stress and the saturated state).
  virtual void initialise(PointSet& points, PointRange range) const { (void)points; (void)range; }

  // Optional: true if eigenstrain() writes an eigenstrain increment. Read
  // once, at set-up: it must not change during the run.
  virtual bool writes_eigenstrain() const { return false; }
  // Write the eigenstrain increment of this step for the batch, 6 per point
  // (Voigt, tensor components, tension positive), before update_stress. The
  // span arrives zeroed: a point the phase leaves alone gets none. In
  // quasi-static runs it is asked once per step, before the solve, from the
  // state at the step's start, and every Newton iteration's update_stress
  // gets the same increment: it may not depend on the velocity gradient.
  virtual void eigenstrain(const StressBatch& batch, std::span<double> increment) const {
    (void)batch; (void)increment;
  }

  // Optional, for quasi-static runs (docs/time-integration.md): the tangent
  // stiffness of each point of the batch in its current state, 36 per point
  // (point p at (p - range.begin) * 36): 6x6 row-major, Voigt order, acting on
  // engineering strain increments (tensor::isotropic_stiffness builds the
  // elastic one). The implicit solve iterates on the true stresses, so an
  // elastic stiffness is enough to converge (a modified Newton method); a
  // consistent tangent converges in fewer iterations. Return false to let
  // the core use an isotropic stiffness of modulus p_wave_modulus() and
  // Poisson's ratio 0.3.
  virtual bool tangent(const StressBatch& batch, std::span<double> stiffness) const {
    (void)batch; (void)stiffness;
    return false;
  }

  // Optional: the elastic (unloading) stiffness of each point in its current
  // state, in tangent()'s form: the stiffness a stress follows when a strain
  // the phase imposes unloads it (phase/suffosion's "substeps" integration
  // relaxes a point under its own erosion-induced strain with it). The
  // default returns tangent(), right for a phase whose tangent is elastic;
  // a plastic tangent (phase/mohr_coulomb's) overrides it.
  virtual bool elastic_stiffness(const StressBatch& batch, std::span<double> stiffness) const {
    return tangent(batch, stiffness);
  }

  // Optional: true if the phase divides its strength by the batch's
  // strength_reduction (the shear strength reduction that gives a factor of
  // safety). A scene asks for a factor of safety only where some phase does.
  virtual bool reduces_strength() const { return false; }

  // Advance the stress (and the phase's own state) of the batch over dt.
  // Called from several threads at once on disjoint batches: write only the
  // batch's points, keep no mutable member state.
  virtual void update_stress(const StressBatch& batch) const = 0;
};

}  // namespace suffuse
