#include "mpm/reactions.hpp"

#include <algorithm>
#include <ostream>

#include "parallel/executor.hpp"
#include "suffuse/error.hpp"
#include "mpm/solid_kernels.hpp"

namespace suffuse::detail {

Reactions::Reactions(const std::vector<ReactionSpec>& specs, int dim) : dim_(dim) {
  for (const ReactionSpec& s : specs) records_.push_back({s.condition, s.name});
}

namespace {
// The nodal velocities of the nodes this process updates (the others are
// never read: Domain::node_sums takes only nodes a process owns).
void copy_velocities(const Domain& domain, std::vector<double>& into) {
  const std::vector<double>& v = domain.nodes.velocity;
  const ScatterRange r = domain.node_range();
  const auto D = static_cast<std::size_t>(domain.dim());
  into.resize(v.size());
  std::copy(v.begin() + static_cast<std::ptrdiff_t>(r.first * D), v.begin() + static_cast<std::ptrdiff_t>(r.last * D),
            into.begin() + static_cast<std::ptrdiff_t>(r.first * D));
}
}  // namespace

void Reactions::start_constraints(const Domain& domain, double damping) {
  damping_ = damping;
  if (!records_.empty()) copy_velocities(domain, free_);
}

void Reactions::constrain(std::size_t b, const BoundaryCondition& bc, Domain& domain, double time, double dt) {
  NodeState& nodes = domain.nodes;
  const auto record = std::find_if(records_.begin(), records_.end(), [&](const Record& r) { return r.condition == b; });
  if (record == records_.end()) {
    bc.constrain_velocity(domain.grid, nodes, time);
    return;
  }
  copy_velocities(domain, before_);
  bc.constrain_velocity(domain.grid, nodes, time);
  const int D = dim_;
  // Per axis: the momentum the constraint adds, the mass it holds and that
  // mass's momentum; summed in node order, each node by its owner.
  const Domain::NodeTerms sums = domain.node_sums(3 * D, [&](std::size_t I, double* t) {
    const double m = nodes.mass[I];
    if (m <= 0) return false;
    bool held = false;
    for (int i = 0; i < D; ++i) {
      const double v = nodes.velocity[I * D + i], free = free_[I * D + i];
      if (v == before_[I * D + i]) continue;  // not this condition's
      // The node's unbalanced force without the (numerical) local damping:
      // the reaction balances that force, not the damping's.
      const double v_old = nodes.momentum[I * D + i] / m;
      const double damped_force = m * (free - v_old) / dt;
      t[i] = m * (v - v_old) - undamped(damped_force, v_old, damping_) * dt;
      t[D + i] = m;
      t[2 * D + i] = m * v;
      held = true;
    }
    return held;
  });
  for (int i = 0; i < D; ++i) {
    record->impulse[i] += sums[i];
    const double mass = sums[D + i];
    if (mass > 0) record->displacement[i] += sums[2 * D + i] / mass * dt;
  }
  record->elapsed += dt;
}

void Reactions::add_equilibrium(std::size_t r, const std::array<double, 3>& force,
                                const std::array<double, 3>& displacement, double dt) {
  Record& record = records_[r];
  for (int i = 0; i < dim_; ++i) {
    record.impulse[i] += force[i] * dt;
    record.displacement[i] += displacement[i];
  }
  record.elapsed += dt;
}

void Reactions::write_header(std::ostream& out) const {
  const char* axes = "xyz";
  const std::string force_unit = dim_ == 2 ? "N/m" : "N";
  out << "time [s]";
  for (const Record& r : records_) {
    for (int i = 0; i < dim_; ++i) out << ',' << r.name << " F" << axes[i] << " [" << force_unit << ']';
    for (int i = 0; i < dim_; ++i) out << ',' << r.name << " u" << axes[i] << " [m]";
  }
  out << '\n';
}

void Reactions::write_row(std::ostream& out, double time) {
  out << time;
  for (Record& r : records_) {
    for (int i = 0; i < dim_; ++i) out << ',' << (r.elapsed > 0 ? r.impulse[i] / r.elapsed : 0.0);
    for (int i = 0; i < dim_; ++i) out << ',' << r.displacement[i];
    r.impulse = {};
    r.elapsed = 0;
  }
  out << '\n';
}

std::vector<double> Reactions::saved_state() const {
  std::vector<double> state;
  for (const Record& r : records_) {
    state.insert(state.end(), r.impulse.begin(), r.impulse.end());
    state.insert(state.end(), r.displacement.begin(), r.displacement.end());
    state.push_back(r.elapsed);
  }
  return state;
}

void Reactions::restore_state(const std::vector<double>& state) {
  if (state.size() != records_.size() * 7)
    throw Error("checkpoint: " + std::to_string(state.size() / 7) + " reactions saved, the scene records " +
                std::to_string(records_.size()));
  auto v = state.begin();
  for (Record& r : records_) {
    std::copy(v, v + 3, r.impulse.begin());
    std::copy(v + 3, v + 6, r.displacement.begin());
    r.elapsed = v[6];
    v += 7;
  }
}

}  // namespace suffuse::detail
