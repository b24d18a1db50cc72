// The transport's backward-Euler step (TransportScheme::backward_euler): the
// rest of a quasi-static step once its transport is steady. First-order
// upwind on the dual cells and face volumes of the explicit stages, implicit
// in the nodal amounts U:
//
//   (I + A) U' = U + inflow,   A_II = (volume leaving I) / pore_I,
//                              A_IJ = -(volume J sends I) / pore_J.
//
// I + A has a positive diagonal, non-positive off-diagonals and column sums
// of at least one (what leaves a node through the grid's boundary adds to
// its column): an M-matrix, so any step is stable, no amount turns negative,
// and the fines stay within the carrying liquid within the liquid. One
// matrix serves the three amounts. The nodal changes are then formed from
// the transfers the solution implies, so the ledger closes to round-off
// whatever the residual of the solve.
//
// On many processes every process gathers every node's amounts (from the
// nodes' owners) and the matrix is PETSc's (DistributedSystem), each process
// adding its rows; the solution comes back whole to every process, which
// then books the same transfers.
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <algorithm>
#include <vector>

#include "parallel/distributed_system.hpp"
#include "transport/species_kernels.hpp"
#include "transport/species_transport.hpp"
#include "suffuse/error.hpp"

namespace suffuse::detail {

void SpeciesTransport::implicit_stage(double dt) {
  const int dim = d_.dim();
  const bool fines = fines_.has_value();
  const std::size_t nn = d_.grid.node_count();
  const TransportGrid g{d_.grid.nodes_per_axis(), d_.grid.cell_size(), dt, node_pore_.data(), node_liquid_.data(),
                        fines ? node_fines_.data() : nullptr, fines ? node_carrying_.data() : nullptr,
                        node_darcy_.data(), node_face_.data(), inflow_liquid_.data(), inflow_fines_.data(),
                        inflow_carrying_.data()};
  if (d_.comm.parallel()) {  // every node's amounts on every process
    for (auto* v : {&node_pore_, &node_liquid_}) d_.gather_nodal_to_all(d_.shape, *v, 1);
    if (fines)
      for (auto* v : {&node_fines_, &node_carrying_}) d_.gather_nodal_to_all(d_.shape, *v, 1);
  }
  const double* pore = node_pore_.data();
  // What leaves or enters each node through the open faces, per opening
  // node: the volume (positive out) this step.
  auto opening_volume = [&](const auto& transport, const Opening& o, const OpeningNode& on) {
    return pore[on.node] > 0 ? dt * on.area * o.face.outward() * transport.darcy(on.node, o.face.axis) : 0.0;
  };

  auto run = [&](auto transport) {
    transport.faces(0, nn);  // node_face_: volume crossing to I + e_a, positive forward
    const double* face = node_face_.data();
    // node_out_: volume leaving each node, through every kind of face.
    for (std::size_t I = 0; I < nn; ++I) {
      const auto c = transport.ijk(static_cast<std::int64_t>(I));
      double out = transport.free_surface_volume(static_cast<std::int64_t>(I), c);
      for (int a = 0; a < dim; ++a) {
        if (c[a] < g.nodes[a] - 1) out += std::max(0.0, face[I * dim + a]);
        if (c[a] > 0) out += std::max(0.0, -face[(I - transport.stride(a)) * dim + a]);
      }
      node_out_[I] = out;
    }
    std::fill(node_dliquid_.begin(), node_dliquid_.end(), 0.0);  // here: what enters through open faces
    std::fill(node_dfines_.begin(), node_dfines_.end(), 0.0);
    std::fill(node_dcarrying_.begin(), node_dcarrying_.end(), 0.0);
    for (const Opening& o : openings_)
      for (const OpeningNode& on : o.nodes) {
        const double vol = opening_volume(transport, o, on);
        const std::size_t at = static_cast<std::size_t>(on.node) * dim + o.face.axis;
        if (vol > 0) {
          node_out_[on.node] += vol;
        } else if (vol < 0) {
          node_dliquid_[on.node] -= vol * inflow_liquid_[at];
          node_dfines_[on.node] -= vol * inflow_fines_[at];
          node_dcarrying_[on.node] -= vol * inflow_carrying_[at];
        }
      }

    std::vector<Eigen::Triplet<double>> entries;  // once per quasi-static step, not per substep
    entries.reserve(nn * (1 + dim));
    for (std::size_t I = 0; I < nn; ++I) {
      const auto row = static_cast<int>(I);
      if (!(pore[I] > 0)) {  // no liquid: nothing moves
        entries.emplace_back(row, row, 1.0);
        continue;
      }
      entries.emplace_back(row, row, 1 + node_out_[I] / pore[I]);
      const auto c = transport.ijk(static_cast<std::int64_t>(I));
      for (int a = 0; a < dim; ++a) {
        const auto s = static_cast<std::size_t>(transport.stride(a));
        if (c[a] < g.nodes[a] - 1 && face[I * dim + a] < 0)  // I + e_a sends to I
          entries.emplace_back(row, static_cast<int>(I + s), face[I * dim + a] / pore[I + s]);
        if (c[a] > 0 && face[(I - s) * dim + a] > 0)  // I - e_a sends to I
          entries.emplace_back(row, static_cast<int>(I - s), -face[(I - s) * dim + a] / pore[I - s]);
      }
    }
    const auto size = static_cast<Eigen::Index>(nn);
    Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> solver;
    if (d_.comm.parallel()) {
      if (!implicit_system_)
        implicit_system_ = make_distributed_system(d_.comm, "transport: the backward-Euler step",
                                                               "suffuse_transport_");
      DistributedSystem& system = *implicit_system_;
      system.start(nn);
      const auto [first, last] = system.rows();
      std::erase_if(entries, [first = first, last = last](const Eigen::Triplet<double>& e) {
        return static_cast<std::size_t>(e.row()) < first || static_cast<std::size_t>(e.row()) >= last;
      });
      system.add(entries, static_cast<std::size_t>(1 + 2 * dim));
      system.finish(false);
    } else {
      Eigen::SparseMatrix<double> matrix(size, size);
      matrix.setFromTriplets(entries.begin(), entries.end());
      // Direct: robust for any flux pattern and cheap at a grid's node count
      // (the matrix is a tridiagonal-like band per axis); once per step.
      solver.compute(matrix);
      if (solver.info() != Eigen::Success)
        throw Error("transport: the backward-Euler step's matrix could not be factorised (" +
                    solver.lastErrorMessage() + ")");
    }
    std::vector<double> rhs(nn);
    auto solve = [&](const std::vector<double>& amount, const std::vector<double>& inflow, std::vector<double>& next) {
      for (std::size_t I = 0; I < nn; ++I) rhs[I] = amount[I] + inflow[I];
      if (implicit_system_) {
        implicit_system_->solve(rhs, next);
        return;
      }
      Eigen::Map<Eigen::VectorXd>(next.data(), size) = solver.solve(Eigen::Map<const Eigen::VectorXd>(rhs.data(), size));
    };
    solve(node_liquid_, node_dliquid_, stage_liquid_);
    if (fines) {
      solve(node_fines_, node_dfines_, stage_fines_);
      solve(node_carrying_, node_dcarrying_, stage_carrying_);
    }

    // The transfers the new amounts imply, each between two accounts.
    const double* liquid = stage_liquid_.data();
    const double* fines_at = fines ? stage_fines_.data() : nullptr;
    const double* carrying = fines ? stage_carrying_.data() : nullptr;
    for (auto& account : discharge_step_) account = {0, 0, 0, 0};
    auto send = [&](std::size_t from, std::size_t to, double volume) {  // volume > 0 from `from` to `to`
      const double share = volume / pore[from];
      const double moved = share * liquid[from];
      node_dliquid_[from] -= moved, node_dliquid_[to] += moved;
      if (!fines) return;
      const double f = share * fines_at[from], carried = share * carrying[from];
      node_dfines_[from] -= f, node_dfines_[to] += f;
      node_dcarrying_[from] -= carried, node_dcarrying_[to] += carried;
    };
    for (std::size_t I = 0; I < nn; ++I) {
      const auto c = transport.ijk(static_cast<std::int64_t>(I));
      for (int a = 0; a < dim; ++a) {
        if (c[a] == g.nodes[a] - 1) continue;
        const std::size_t J = I + static_cast<std::size_t>(transport.stride(a));
        const double vol = face[I * dim + a];
        if (vol > 0) send(I, J, vol);
        if (vol < 0) send(J, I, -vol);
      }
      const double free = transport.free_surface_volume(static_cast<std::int64_t>(I), c);
      if (free > 0) discharge(I, free / pore[I], liquid, fines_at, carrying, discharge_step_.back());
    }
    for (std::size_t k = 0; k < openings_.size(); ++k) {
      const Opening& o = openings_[k];
      for (const OpeningNode& on : o.nodes) {
        const double vol = opening_volume(transport, o, on);
        const auto I = static_cast<std::size_t>(on.node);
        if (vol > 0) {
          discharge(I, vol / pore[I], liquid, fines_at, carrying, discharge_step_[k]);
        } else if (vol < 0) {  // already in node_d*, from the right-hand side
          const std::size_t at = I * dim + o.face.axis;
          discharge_step_[k][1] -= vol * inflow_liquid_[at];
          discharge_step_[k][3] -= vol * inflow_fines_[at];
        }
      }
    }
  };
  if (dim == 2)
    run(Transport<2>{g});
  else
    run(Transport<3>{g});
}

}  // namespace suffuse::detail
