#include "io/grid_projection.hpp"

#include <algorithm>

#include "mixture/saturated_mixture.hpp"

namespace suffuse::detail {

namespace {

// field_I = sum_p N_Ip w_p f_p / sum_p N_Ip w_p; nodes no point reaches stay 0.
// The sums go through the executor's scatter: on many processes each node
// sums every process's points, in the serial run's order.
template <int D>
void weighted_mean(Domain& d, const Interpolation& shape, const double* w, const double* f, int k, GridField& out,
                   std::vector<double>& weight) {
  std::fill(out.values.begin(), out.values.end(), 0.0);
  std::fill(weight.begin(), weight.end(), 0.0);
  ScatterTargets targets = shape.targets(weight.size());
  targets.add(weight);
  targets.add(out.values);
  const PointSupports s = shape.view();
  d.exec.scatter(d.points.size(), targets, [&](std::size_t b, std::size_t e, double* const* sums) {
    for (std::size_t p = b; p < e; ++p)
      for_each_weight<D>(s, p, [&](std::size_t I, double N) {
        const double nw = N * w[p];
        sums[0][I] += nw;
        for (int c = 0; c < k; ++c) sums[1][I * k + c] += nw * f[p * k + c];
      });
  });
  d.periodic.fold(weight, 1);  // a periodic grid's images: the nodes they are (mpm/periodic_grid.hpp)
  d.periodic.fold(out.values, k);
  for (std::size_t I = 0; I < weight.size(); ++I)
    for (int c = 0; c < k; ++c) out.values[I * k + c] = weight[I] > 0 ? out.values[I * k + c] / weight[I] : 0.0;
  d.periodic.copy_to_images(out.values, k);
  d.periodic.copy_to_images(weight, 1);
}

}  // namespace

const std::vector<GridField>& GridProjection::project(Domain& d) {
  const int D = d.dim();
  const std::size_t nodes = d.grid.node_count(), n = d.points.size();
  const auto& core = d.points.core();
  if (fields_.empty()) {
    fields_.push_back({"mass", D == 2 ? "kg/m" : "kg", "solid mass on the node, sum N m (per metre in 2D)", 1, {}});
    fields_.push_back({"velocity", "m/s", "velocity of the skeleton, mass-weighted", D, {}});
    if (mixture_) {
      fields_.push_back({"liquid_velocity", "m/s", "velocity of the pore liquid, liquid-mass-weighted", D, {}});
      fields_.push_back({"pore_pressure", "Pa", "pore pressure, compression positive, volume-weighted", 1, {}});
      fields_.push_back({"darcy_flux", "m/s", "Darcy flux n (v_L - v_s), the nodal flux the transport uses", D, {}});
    }
    for (GridField& f : fields_) f.values.resize(nodes * f.components);
    weight_.resize(nodes);
  }
  d.evaluate_shape(shape_);
  const auto mean = D == 2 ? &weighted_mean<2> : &weighted_mean<3>;
  const double* mass = d.points.data(core.mass);
  const double* volume = d.points.data(core.volume);
  const std::vector<double> ones(n, 1.0);
  mean(d, shape_, mass, ones.data(), 1, fields_[0], weight_);
  for (std::size_t I = 0; I < nodes; ++I) fields_[0].values[I] = weight_[I];  // the sum itself
  mean(d, shape_, mass, d.points.data(core.velocity), D, fields_[1], weight_);
  if (mixture_) {
    const MixtureFields& m = *mixture_;
    mean(d, shape_, d.points.data(m.liquid_mass), d.points.data(m.liquid_velocity), D, fields_[2], weight_);
    mean(d, shape_, volume, d.points.data(m.pressure), 1, fields_[3], weight_);
    fields_[4].values = *nodal_darcy_;
  }
  // On many processes each node's values are complete on the processes
  // whose points reach it: its owner's go to the first process, which writes.
  // The Darcy flux is the step's, complete where the step's shape functions
  // reached (the points have moved since); before the first step it is
  // zero everywhere, as in the serial run.
  for (std::size_t k = 0; k < fields_.size(); ++k) {
    const Interpolation& made_by = mixture_ && k == 4 ? d.shape : shape_;
    if (d.owners_known(made_by)) d.gather_nodal_to_root(made_by, fields_[k].values, fields_[k].components);
  }
  return fields_;
}

}  // namespace suffuse::detail
