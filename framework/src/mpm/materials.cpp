#include "mpm/materials.hpp"

#include <algorithm>

#include "mpm/plugin_batch.hpp"
#include "suffuse/tensor.hpp"

namespace suffuse::detail {

Materials::Materials(const Scene& scene, const Registry& registry) {
  phases_.reserve(scene.materials.size());
  for (const MaterialSpec& m : scene.materials) {
    phases_.emplace_back(registry, m.phase, m.base, scene.dim);
    names_.push_back(plugin_of_material("phase", m.phase, m.name));
  }
}

std::vector<const Phase*> Materials::phases() const {
  std::vector<const Phase*> all;
  for (const auto& p : phases_) all.push_back(&p.phase());
  return all;
}

void Materials::add_fields(PointSet& points) {
  const std::size_t first = points.field_count();
  for (const auto& material : phases_) {
    if (!material.phase().writes_eigenstrain() || eigenstrain_) continue;
    using K = FieldKind;
    eigenstrain_ = points.add_field(
        {"eigenstrain", K::SymmetricTensor, "-", "inelastic strain imposed by the phase, accumulated", true});
    eigenstrain_increment_ = points.add_field(
        {"eigenstrain_increment", K::SymmetricTensor, "-", "the eigenstrain of the last step", false});
  }
  for (auto& material : phases_) material.add_fields(points);
  state_fields_ = {points.core().stress};
  for (FieldId id = first; id < points.field_count(); ++id) state_fields_.push_back(id);
}

bool Materials::reduces_strength() const {
  return std::any_of(phases_.begin(), phases_.end(), [](const MaterialPhase& m) { return m.phase().reduces_strength(); });
}

void Materials::tangent(Domain& d, double dt, std::vector<double>& stiffness, double strength_reduction) const {
  stiffness.resize(d.points.size() * 36);
  for (const BodyPoints& body : d.bodies) {
    const Phase& phase = phases_[body.material].phase();
    d.exec.for_chunks(body.range.size(), [&](int, std::size_t b, std::size_t e) {
      const PointRange range{body.range.begin + b, body.range.begin + e};
      const std::span<double> D(stiffness.data() + range.begin * 36, range.size() * 36);
      if (phase.tangent(StressBatch{d.points, range, dt, {}, strength_reduction}, D)) return;
      const double M = phase.p_wave_modulus(), nu = 0.3;
      const double G = M * (1 - 2 * nu) / (2 * (1 - nu));
      for (std::size_t k = 0; k < range.size(); ++k) tensor::isotropic_stiffness(M - 4 * G / 3, G, D.data() + k * 36);
    });
  }
}

template <class F>
void Materials::for_each_batch(Domain& d, const F& f) const {
  for (const BodyPoints& body : d.bodies) {
    const Phase& phase = phases_[body.material].phase();
    d.exec.for_chunks(body.range.size(), [&](int, std::size_t b, std::size_t e) {
      const PointRange range{body.range.begin + b, body.range.begin + e};
      run_plugin_on_batch(d, body, range, names_[body.material], [&] { f(phase, range); });
    });
  }
}

// The phase's eigenstrain increment of the step into "eigenstrain_increment",
// added to the accumulated "eigenstrain".
void Materials::impose_eigenstrain(const Phase& phase, PointSet& points, const PointRange& range, double dt) const {
  if (!phase.writes_eigenstrain()) return;
  const std::span<double> increment(points.data(*eigenstrain_increment_) + range.begin * 6, range.size() * 6);
  std::fill(increment.begin(), increment.end(), 0.0);  // a point the phase skips gets none
  phase.eigenstrain(StressBatch{points, range, dt, {}}, increment);
  double* total = points.data(*eigenstrain_) + range.begin * 6;
  for (std::size_t k = 0; k < increment.size(); ++k) total[k] += increment[k];
}

std::span<const double> Materials::imposed_eigenstrain(const Phase& phase, PointSet& points,
                                                       const PointRange& range) const {
  if (!phase.writes_eigenstrain()) return {};
  return {points.data(*eigenstrain_increment_) + range.begin * 6, range.size() * 6};
}

void Materials::update_stress(Domain& d, double dt) const {
  for_each_batch(d, [&](const Phase& phase, const PointRange& range) {
    impose_eigenstrain(phase, d.points, range, dt);
    phase.update_stress(StressBatch{d.points, range, dt, imposed_eigenstrain(phase, d.points, range), 1.0, false});
  });
}

void Materials::impose_eigenstrain(Domain& d, double dt) const {
  for_each_batch(d, [&](const Phase& phase, const PointRange& range) { impose_eigenstrain(phase, d.points, range, dt); });
}

void Materials::update_stress_with_imposed_eigenstrain(Domain& d, double dt, double strength_reduction) const {
  for_each_batch(d, [&](const Phase& phase, const PointRange& range) {
    phase.update_stress(
        StressBatch{d.points, range, dt, imposed_eigenstrain(phase, d.points, range), strength_reduction, true});
  });
}

}  // namespace suffuse::detail
