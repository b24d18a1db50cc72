// The sparse system of a quasi-static step and its factorisation (private to
// quasi_static.cpp and quasi_static_assembly.cpp).
#pragma once

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <memory>
#include <vector>

#include "distributed_system.hpp"
#include "quasi_static.hpp"
#include "suffuse/error.hpp"

namespace suffuse::detail {

// Whether a point's 6x6 tangent is zero (a stress at the apex of a yield
// surface, a point that separated): the creep term holds its nodes.
inline bool without_stiffness(const double* D) { return D[0] == 0 && D[7] == 0 && D[14] == 0 && D[35] == 0; }

struct QuasiStatic::Linear {
  static constexpr const char* singular =
      "a body that nothing holds (check the velocity conditions), or pore pressure with no face to drain to and no "
      "storage";
  using Matrix = Eigen::SparseMatrix<double>;
  std::vector<Eigen::Triplet<double>> triplets;
  Matrix matrix;
  Eigen::VectorXd scale;  // symmetric diagonal scaling: the blocks differ by many orders of magnitude
  // Symmetric tangents: LDL' (half the work and memory of LU). A tangent
  // that is not symmetric (Mohr-Coulomb's with psi < phi): LU.
  bool symmetric = true;
  Eigen::SimplicialLDLT<Matrix, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt;
  Eigen::SparseLU<Matrix, Eigen::COLAMDOrdering<int>> lu;
  // The pattern is that of the step (QuasiStatic::prepare_blocks): its
  // ordering and symbolic analysis are done once per step and solver.
  bool ldlt_analysed = false, lu_analysed = false;
  // On many processes: PETSc's (the Eigen members above stay unused), and
  // whether its matrix has this step's pattern yet.
  std::unique_ptr<DistributedSystem> distributed;
  bool distributed_started = false;

  double scale_of(std::size_t e) const {
    return distributed ? distributed->scale()[e] : scale[static_cast<Eigen::Index>(e)];
  }

  bool factorise() {
    if (symmetric && !ldlt_analysed) ldlt.analyzePattern(matrix), ldlt_analysed = true;
    if (!symmetric && !lu_analysed) lu.analyzePattern(matrix), lu_analysed = true;
    if (symmetric) {
      ldlt.factorize(matrix);
      return ldlt.info() == Eigen::Success;
    }
    lu.factorize(matrix);
    return lu.info() == Eigen::Success;
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
    const Eigen::VectorXd scaled = scale.asDiagonal() * rhs;
    return scale.asDiagonal() * (symmetric ? Eigen::VectorXd(ldlt.solve(scaled)) : Eigen::VectorXd(lu.solve(scaled)));
  }
};

}  // namespace suffuse::detail
