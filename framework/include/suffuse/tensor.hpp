#pragma once
// Small-tensor helpers for constitutive models: Voigt storage, invariants and
// the soil-mechanics stress measures.
//
// Storage: a symmetric tensor is 6 numbers in the order xx, yy, zz, yz, xz, xy
// (tensor components, not engineering shear strains), in 2D (plane strain,
// sigma_zz kept) and 3D alike. Sign: the core's convention, tension positive.
// The soil-mechanics measures below (mean effective stress p', deviatoric
// stress q, eta = q/p', volumetric and deviatoric strain) are COMPRESSION
// POSITIVE, as in the soil-mechanics literature and the element tests.
#include <array>
#include <cmath>

namespace suffuse::tensor {

using Voigt = std::array<double, 6>;         // xx yy zz yz xz xy
using Matrix = std::array<std::array<double, 3>, 3>;

// Index of component (i, j) of a symmetric tensor in Voigt storage.
constexpr int voigt_index(int i, int j) {
  if (i == j) return i;
  const int s = i + j;
  return s == 3 ? 3 : (s == 2 ? 4 : 5);
}

inline Matrix to_matrix(const double* v) {
  return {{{v[0], v[5], v[4]}, {v[5], v[1], v[3]}, {v[4], v[3], v[2]}}};
}
inline Voigt to_voigt(const Matrix& m) { return {m[0][0], m[1][1], m[2][2], m[1][2], m[0][2], m[0][1]}; }
inline void store(const Matrix& m, double* v) {
  const Voigt s = to_voigt(m);
  for (int c = 0; c < 6; ++c) v[c] = s[c];
}

inline double trace(const double* v) { return v[0] + v[1] + v[2]; }

// Deviator s = sigma - (tr sigma / 3) I.
inline Voigt deviator(const double* v) {
  const double m = trace(v) / 3;
  return {v[0] - m, v[1] - m, v[2] - m, v[3], v[4], v[5]};
}

// s : s for a symmetric tensor (shear components count twice).
inline double double_contraction(const double* a, const double* b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + 2 * (a[3] * b[3] + a[4] * b[4] + a[5] * b[5]);
}

// Invariants: I1 = tr sigma, J2 = s:s / 2, J3 = det s.
inline double first_invariant(const double* v) { return trace(v); }
inline double second_deviatoric_invariant(const double* v) {
  const Voigt s = deviator(v);
  return 0.5 * double_contraction(s.data(), s.data());
}
inline double third_deviatoric_invariant(const double* v) {
  const Voigt s = deviator(v);
  return s[0] * s[1] * s[2] + 2 * s[3] * s[4] * s[5] - s[0] * s[3] * s[3] - s[1] * s[4] * s[4] -
         s[2] * s[5] * s[5];
}
// Lode angle theta in [-pi/6, pi/6]: sin 3 theta = -(3 sqrt 3 / 2) J3 / J2^(3/2); 0 where J2 = 0.
// Of a tension-positive stress: +pi/6 in triaxial compression, -pi/6 in triaxial extension.
inline double lode_angle(const double* v) {
  const double j2 = second_deviatoric_invariant(v);
  if (!(j2 > 0)) return 0.0;
  double s = -1.5 * std::sqrt(3.0) * third_deviatoric_invariant(v) / std::pow(j2, 1.5);
  s = std::fmax(-1.0, std::fmin(1.0, s));
  return std::asin(s) / 3;
}

// Isotropic linear elasticity with the Jaumann stress rate, one increment:
// sigma + 2 G d + lambda tr(d) I + w sigma - sigma w, for the strain and spin
// increments d and w of a step, so that a rigid rotation creates no stress.
inline Matrix jaumann_elastic_increment(const Matrix& s, const Matrix& d, const Matrix& w, double G, double lambda) {
  const double tr = d[0][0] + d[1][1] + d[2][2];
  Matrix next;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double rotation = 0;
      for (int k = 0; k < 3; ++k) rotation += w[i][k] * s[k][j] - s[i][k] * w[k][j];
      next[i][j] = s[i][j] + 2 * G * d[i][j] + (i == j ? lambda * tr : 0.0) + rotation;
    }
  return next;
}

// Soil mechanics, compression positive.
// Mean stress p = -tr sigma / 3 (of the effective stress: p').
// Isotropic elastic stiffness of bulk modulus K and shear modulus G, 6x6
// row-major in Voigt order (xx, yy, zz, yz, xz, xy), acting on engineering
// strains (shear components 2 eps_ij): the form Phase::tangent() returns.
inline void isotropic_stiffness(double K, double G, double* D) {
  const double lambda = K - 2 * G / 3;
  for (int i = 0; i < 36; ++i) D[i] = 0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) D[i * 6 + j] = lambda;
    D[i * 6 + i] += 2 * G;
    D[(i + 3) * 6 + i + 3] = G;
  }
}

inline double mean_stress(const double* sigma) { return -trace(sigma) / 3; }
// Deviatoric stress q = sqrt(3 J2).
inline double deviatoric_stress(const double* sigma) { return std::sqrt(3 * second_deviatoric_invariant(sigma)); }
// Stress ratio eta = q / p'; 0 where p' <= 0 (no confinement: no ratio to speak of).
inline double stress_ratio(const double* sigma) {
  const double p = mean_stress(sigma);
  return p > 0 ? deviatoric_stress(sigma) / p : 0.0;
}
// Volumetric strain eps_v = -tr eps (compaction positive).
inline double volumetric_strain(const double* eps) { return -trace(eps); }
// Deviatoric (shear) strain eps_s = sqrt(2/3 e:e), e the strain deviator; the
// work-conjugate of q (p' eps_v + q eps_s is the work per volume).
inline double deviatoric_strain(const double* eps) {
  const Voigt e = deviator(eps);
  return std::sqrt(2.0 / 3.0 * double_contraction(e.data(), e.data()));
}

}  // namespace suffuse::tensor
