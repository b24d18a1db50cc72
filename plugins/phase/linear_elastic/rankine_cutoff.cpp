// Rankine's tension cut-off: see rankine_cutoff.hpp.
#include "rankine_cutoff.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace suffuse::linear_elastic {

int rankine_return(const Lame& elastic, tensor::Matrix& trial, double& multiplier) {
  const double lambda = elastic.lambda, G = elastic.G;
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = trial[i][j];
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> e(m);
  const Eigen::Vector3d s = e.eigenvalues();  // ascending: s(2) the largest
  const double a = lambda + 2 * G, l = lambda;
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  int separated = 1;
  const double g = s(2) / a;
  if (s(1) - l * g <= 0) {
    r = {s(0) - l * g, s(1) - l * g, 0.0};
    multiplier = g;
  } else {
    const double det = a * a - l * l, ga = (a * s(2) - l * s(1)) / det, gb = (a * s(1) - l * s(2)) / det;
    r(0) = std::min(s(0) - l * (ga + gb), 0.0);
    separated = r(0) < 0 ? 2 : 3;
    multiplier = std::min(ga, gb);
  }
  if (separated == 3) {  // exactly no stress: the tangent knows a separated point by it
    trial = {};
    return 3;
  }
  const Eigen::Matrix3d back = e.eigenvectors() * r.asDiagonal() * e.eigenvectors().transpose();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) trial[i][j] = (back(i, j) + back(j, i)) / 2;
  return separated;
}

void rankine_tangent(const Lame& elastic, const double* s6, double multiplier, double* D) {
  const double lambda = elastic.lambda, G = elastic.G;
  const auto M = tensor::to_matrix(s6);
  Eigen::Matrix3d m;
  double scale = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = M[i][j], scale = std::max(scale, std::abs(M[i][j]));
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> e(m);
  bool cut[3];
  int cuts = 0;
  for (int i = 0; i < 3; ++i) cuts += cut[i] = e.eigenvalues()(i) >= -1e-12 * scale;
  if (cuts == 0) return;
  Eigen::Matrix3d normal = Eigen::Matrix3d::Constant(lambda);
  normal.diagonal().array() += 2 * G;
  for (int c = 0; c < 3; ++c) {  // condense each separated direction out in turn
    if (!cut[c]) continue;
    const Eigen::Vector3d column = normal.col(c);
    const double pivot = column(c);
    normal -= pivot > 0 ? Eigen::Matrix3d(column * column.transpose() / pivot) : Eigen::Matrix3d(normal);
  }

  // The shear across two principal directions keeps (s_a - s_b) / (s_a -
  // s_b)_trial of Hooke's: all of it between two that carry stress (the
  // return shifts both alike), none between two separated ones, and
  // between a separated one and another s / (2 G d_gamma + s), s the
  // other's |stress|, d_gamma the return's multiplier.
  const auto shear_share = [&](int a, int b) {
    if (!cut[a] && !cut[b]) return 1.0;
    if (cut[a] && cut[b]) return 0.0;
    const double other = std::abs(e.eigenvalues()(cut[a] ? b : a));
    return other > 0 ? other / (2 * G * multiplier + other) : 0.0;
  };
  const Eigen::Matrix3d& R = e.eigenvectors();
  const int voigt[6][2] = {{0, 0}, {1, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}};
  for (int k = 0; k < 6; ++k) {  // column k: the stress of unit engineering strain k
    Eigen::Matrix3d strain = Eigen::Matrix3d::Zero();
    const auto [i, j] = voigt[k];
    if (i == j)
      strain(i, j) = 1;
    else
      strain(i, j) = strain(j, i) = 0.5;
    const Eigen::Matrix3d principal = R.transpose() * strain * R;
    Eigen::Matrix3d stress = Eigen::Matrix3d::Zero();
    stress.diagonal() = normal * principal.diagonal();
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        if (a != b) stress(a, b) = shear_share(a, b) * 2 * G * principal(a, b);
    const Eigen::Matrix3d global = R * stress * R.transpose();
    for (int r = 0; r < 6; ++r) D[r * 6 + k] = global(voigt[r][0], voigt[r][1]);
  }
}

}  // namespace suffuse::linear_elastic
