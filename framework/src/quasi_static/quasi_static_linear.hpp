// The sparse system of a quasi-static step and its factorisation (private to
// quasi_static.cpp and quasi_static_assembly.cpp).
#pragma once

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <algorithm>
#include <memory>
#include <span>
#include <optional>
#include <unsupported/Eigen/IterativeSolvers>
#include <vector>

#include "parallel/distributed_system.hpp"
#include "quasi_static/quasi_static.hpp"
#include "suffuse/error.hpp"

namespace suffuse::detail {

// Whether a point's 6x6 tangent is zero (a stress at the apex of a yield
// surface, a point that separated): the creep term holds its nodes.
inline bool without_stiffness(const double* D) { return D[0] == 0 && D[7] == 0 && D[14] == 0 && D[35] == 0; }

struct QuasiStatic::Linear {
  static constexpr const char* singular =
      "a body that nothing holds (check the velocity conditions), or pore pressure with no face to drain to and no "
      "storage";
  static constexpr const char* failing =
      "; or, where earlier steps found equilibria, the soil failing: a mechanism without stiffness (give the scene a "
      "/failure section to stop there with its outputs and a checkpoint)";
  using Matrix = Eigen::SparseMatrix<double>;
  std::vector<Eigen::Triplet<double>> triplets;
  Matrix matrix;
  // Per triplet of the step's first assembly, where its value lies in
  // `matrix` (QuasiStatic::assemble); empty until then.
  std::vector<std::size_t> value_at;
  Eigen::VectorXd scale;  // symmetric diagonal scaling: the blocks differ by many orders of magnitude
  // Symmetric tangents: LDL' (half the work and memory of LU). A tangent
  // that is not symmetric (Mohr-Coulomb's with psi < phi): LU.
  bool symmetric = true;
  Eigen::SimplicialLDLT<Matrix, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt;
  Eigen::SparseLU<Matrix, Eigen::COLAMDOrdering<int>> lu;
  // The pattern is that of the step (QuasiStatic::prepare_blocks): its
  // ordering and symbolic analysis are done once per pattern and solver
  // (new_step_pattern).
  bool ldlt_analysed = false, lu_analysed = false;
  // On many processes: PETSc's (the Eigen members above stay unused), and
  // whether its matrix has this step's pattern yet.
  std::unique_ptr<DistributedSystem> distributed;
  bool distributed_started = false;

  double scale_of(std::size_t e) const {
    return distributed ? distributed->scale()[e] : scale[static_cast<Eigen::Index>(e)];
  }

  // Newton iterations after a step's first solve its system by GMRES,
  // preconditioned by the factors of the step's last factorised matrix
  // (solve_reusing_factors). They factorise only where GMRES does not reach
  // gmres_tolerance (its preconditioned residual) in gmres_max_iterations,
  // or leaves a true residual above true_residual_tolerance of the
  // right-hand side. The tangent changes little between iterations: in the
  // levee GMRES takes 13 to 22 iterations, each a pair of triangular solves
  // and a product, where an LU factorisation costs about 34 of them. A
  // correction to 1e-6 keeps Newton's convergence (the same iteration
  // counts). The first solve of every step factorises, so that a step is
  // the same whatever ran before it (a restart is bit for bit the run it
  // continues). Eigen's GMRES holds a dense matrix of (unknowns x 31)
  // values: 250 MB at a million unknowns.
  static constexpr double gmres_tolerance = 1e-6;
  static constexpr int gmres_max_iterations = 30;
  static constexpr double true_residual_tolerance = 1e-5;
  Eigen::VectorXd factor_scale;  // `scale` of the factorised matrix
  bool factor_symmetric = true;
  bool has_factors = false;

  // The unknowns and the pattern of the analysed matrix: the orderings and
  // symbolic analyses stay while the steps' matrices keep them.
  std::vector<std::int64_t> analysed_u_dof, analysed_p_dof;
  std::vector<int> analysed_outer, analysed_inner;
  // After the step's first assembly, `matrix` has the step's pattern.
  void new_step_pattern(const std::vector<std::int64_t>& u_dof, const std::vector<std::int64_t>& p_dof) {
    has_factors = false;
    const auto outer = std::span(matrix.outerIndexPtr(), static_cast<std::size_t>(matrix.outerSize()) + 1);
    const auto inner = std::span(matrix.innerIndexPtr(), static_cast<std::size_t>(matrix.nonZeros()));
    if (u_dof == analysed_u_dof && p_dof == analysed_p_dof && std::ranges::equal(outer, analysed_outer) &&
        std::ranges::equal(inner, analysed_inner))
      return;
    ldlt_analysed = lu_analysed = false;
    analysed_u_dof = u_dof, analysed_p_dof = p_dof;
    analysed_outer.assign(outer.begin(), outer.end());
    analysed_inner.assign(inner.begin(), inner.end());
  }

  bool factorise() {
    if (symmetric && !ldlt_analysed) ldlt.analyzePattern(matrix), ldlt_analysed = true;
    if (!symmetric && !lu_analysed) lu.analyzePattern(matrix), lu_analysed = true;
    factor_scale = scale;
    factor_symmetric = symmetric;
    if (symmetric) {
      ldlt.factorize(matrix);
      has_factors = ldlt.info() == Eigen::Success;
    } else {
      lu.factorize(matrix);
      has_factors = lu.info() == Eigen::Success;
    }
    return has_factors;
  }
  Eigen::VectorXd solve_factorised(const Eigen::VectorXd& scaled) const {
    return factor_symmetric ? Eigen::VectorXd(ldlt.solve(scaled)) : Eigen::VectorXd(lu.solve(scaled));
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& rhs) const {
    if (distributed) {
      std::vector<double> x;
      try {
        distributed->solve({rhs.data(), static_cast<std::size_t>(rhs.size())}, x);
      } catch (const Error& e) {  // as the serial factorisation says (assemble)
        throw Error(std::string(e.what()) + ": the quasi-static system may be singular: " + singular);
      }
      return Eigen::Map<const Eigen::VectorXd>(x.data(), rhs.size());
    }
    return scale.asDiagonal() * solve_factorised(scale.asDiagonal() * rhs);
  }
  // The system of `matrix` (scaled by `scale`) by GMRES, preconditioned by
  // the factors of an earlier matrix A0: with S the current scaling and S0
  // that of the factors, (S A S)^-1 ~ (S A0 S)^-1 = (S0/S) (S0 A0 S0)^-1 (S0/S).
  // Counts GMRES's iterations; nothing if it did not reach the tolerance.
  std::optional<Eigen::VectorXd> solve_reusing_factors(const Eigen::VectorXd& rhs, int& iterations) const {
    if (distributed) {  // PETSc's counterpart, with the same tolerances
      std::vector<double> x;
      if (!distributed->solve_reusing_factors({rhs.data(), static_cast<std::size_t>(rhs.size())}, x, iterations))
        return std::nullopt;
      return Eigen::Map<const Eigen::VectorXd>(x.data(), rhs.size());
    }
    struct Preconditioner {
      const Linear& L;
      Eigen::VectorXd ratio;
      Eigen::VectorXd solve(const Eigen::VectorXd& v) const {
        return ratio.asDiagonal() * L.solve_factorised(ratio.asDiagonal() * v);
      }
    } preconditioner{*this, factor_scale.cwiseQuotient(scale)};
    Eigen::VectorXd x = Eigen::VectorXd::Zero(rhs.size());
    Eigen::Index its = gmres_max_iterations;
    double error = gmres_tolerance;
    const Eigen::VectorXd b = scale.asDiagonal() * rhs;
    Eigen::internal::gmres(matrix, b, x, preconditioner, its,
                           Eigen::Index(gmres_max_iterations), error);
    iterations += static_cast<int>(its);
    if (!(error <= gmres_tolerance) || !x.allFinite()) return std::nullopt;
    // GMRES measured the preconditioned residual. Where the preconditioner
    // is far from the matrix (points that lost their stiffness since the
    // factorisation: a heave) that residual can be small and the true one
    // of the order of the right-hand side; such a solution is refused.
    if (!((b - matrix * x).norm() <= true_residual_tolerance * b.norm())) return std::nullopt;
    return Eigen::VectorXd(scale.asDiagonal() * x);
  }
};

}  // namespace suffuse::detail
