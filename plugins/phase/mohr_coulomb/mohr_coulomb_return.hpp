#pragma once
// Mohr-Coulomb's return mapping in principal stresses (phase/mohr_coulomb):
// the exact return of Clausen, Damkilde & Andersen (2006, 2007) to the
// yield plane, to one of its two edges (triaxial compression and extension
// meridians) or to the apex, with an optional tension cut-off, and its
// consistent tangent. Tension positive, principal stresses s1 >= s2 >= s3.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace suffuse_mohr_coulomb {

using Vec3 = std::array<double, 3>;

inline double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// The return mapping in principal stresses, for stresses sorted s1 >= s2 >= s3.
// Every surface it returns to is a plane in principal stress space, so the
// return is a linear map of the trial stress for a given active set, and its
// consistent tangent follows from that set alone (tangent()).
class MohrCoulombReturn {
 public:
  // The planes a return can end on: the cone's plane, its neighbours across
  // the extension (s2 = s3) and compression (s1 = s2) edges, and the three
  // planes of the tension cut-off s_i <= t.
  enum SurfaceId { plane, extension_edge, compression_edge, cut_off_1, cut_off_2, cut_off_3, surface_count };
  struct Returned {
    Vec3 stress;
    int active = 0;  // how many planes it ended on (0: the trial was admissible)
    int ids[3] = {};
  };

  MohrCoulombReturn(double G, double lambda, double phi, double cohesion, double psi, double tension)
      : G_(G), lambda_(lambda), sin_phi_(std::sin(phi)), k_(2 * cohesion * std::cos(phi)), tension_(tension) {
    const double sp = sin_phi_, sq = std::sin(psi);
    surfaces_[plane] = {{1 + sp, 0, -(1 - sp)}, {1 + sq, 0, -(1 - sq)}, k_};
    surfaces_[extension_edge] = {{1 + sp, -(1 - sp), 0}, {1 + sq, -(1 - sq), 0}, k_};    // beyond s2 = s3
    surfaces_[compression_edge] = {{0, 1 + sp, -(1 - sp)}, {0, 1 + sq, -(1 - sq)}, k_};  // beyond s1 = s2
    for (int i = 0; i < 3; ++i) {
      Vec3 e{0, 0, 0};
      e[i] = 1;
      surfaces_[cut_off_1 + i] = {e, e, tension};
    }
    apex_ = sp > 0 ? k_ / (2 * sp) : std::numeric_limits<double>::infinity();
  }

  double yield(const Vec3& s) const { return dot(surfaces_[plane].a, s) - k_; }
  bool admissible(const Vec3& s, double tol) const { return yield(s) <= tol && s[0] <= tension_ + tol; }

  // The stress on the yield surface the trial stress returns to, and the
  // planes it ended on.
  Returned operator()(const Vec3& trial, double tol) const {
    if (admissible(trial, tol)) return {trial, 0, {}};
    if (yield(trial) > tol) {
      const Returned r = mohr_coulomb(trial, tol);
      if (r.stress[0] <= tension_ + tol) return r;  // the cone alone
    }
    return with_cut_off(trial, tol);
  }

  // d s / d e_trial, the principal stresses' derivatives by the principal
  // (trial) strains, 3x3 row-major, for the return r: the elastic stiffness
  // projected off the active planes, (I - D B A^-1 A') D with B the plastic
  // potentials' gradients, A the yield functions' and A_ij = a_i . D b_j.
  // Three active planes fix all three principal stresses: zero.
  std::array<double, 9> principal_tangent(const Returned& r) const {
    std::array<double, 9> E{};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) E[i * 3 + j] = lambda_ + (i == j ? 2 * G_ : 0.0);
    if (r.active == 0) return E;
    if (r.active == 3) return {};
    const int n = r.active;
    Vec3 Db[2];
    double A[3][3] = {};
    for (int j = 0; j < n; ++j) Db[j] = stiffness(surfaces_[r.ids[j]].b);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) A[i][j] = dot(surfaces_[r.ids[i]].a, Db[j]);
    double inv[2][2];
    if (n == 1) {
      inv[0][0] = 1 / A[0][0];
    } else {
      const double det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
      inv[0][0] = A[1][1] / det, inv[0][1] = -A[0][1] / det, inv[1][0] = -A[1][0] / det, inv[1][1] = A[0][0] / det;
    }
    // P = I - sum_ij Db_i inv_ij a_j', then P E.
    double P[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int row = 0; row < 3; ++row)
          for (int col = 0; col < 3; ++col) P[row][col] -= Db[i][row] * inv[i][j] * surfaces_[r.ids[j]].a[col];
    std::array<double, 9> D{};
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 3; ++col)
        for (int k = 0; k < 3; ++k) D[row * 3 + col] += P[row][k] * E[k * 3 + col];
    return D;
  }

 private:
  struct Surface {
    Vec3 a, b;     // gradients of the yield function and of the plastic potential
    double limit;  // a . s <= limit
  };

  Vec3 stiffness(const Vec3& v) const {  // D v, the isotropic elastic stiffness in principal axes
    const double tr = lambda_ * (v[0] + v[1] + v[2]);
    return {2 * G_ * v[0] + tr, 2 * G_ * v[1] + tr, 2 * G_ * v[2] + tr};
  }

  Returned mohr_coulomb(const Vec3& trial, double tol) const {
    // 1. The plane: one multiplier.
    const Vec3 Db = stiffness(surfaces_[plane].b);
    const double dl = yield(trial) / dot(surfaces_[plane].a, Db);
    const Vec3 s = {trial[0] - dl * Db[0], trial[1] - dl * Db[1], trial[2] - dl * Db[2]};
    if (s[0] >= s[1] - tol && s[1] >= s[2] - tol) return {s, 1, {plane}};
    // 2. An edge: the plane and its neighbour across the violated ordering.
    const SurfaceId other = s[0] < s[1] ? compression_edge : extension_edge;
    Vec3 edge;
    if (on_edge(trial, surfaces_[other], edge, tol)) return {edge, 2, {plane, other}};
    // 3. The apex (none for phi = 0: the edges of Tresca never meet).
    if (std::isfinite(apex_)) return {{apex_, apex_, apex_}, 3, {plane, extension_edge, compression_edge}};
    return {edge, 2, {plane, other}};
  }

  // Two active surfaces: f_i(trial - D (dl_1 b_1 + dl_2 b_2)) = 0, both
  // multipliers non-negative and the result still ordered.
  bool on_edge(const Vec3& trial, const Surface& other, Vec3& out, double tol) const {
    const Surface& main = surfaces_[plane];
    const Vec3 D1 = stiffness(main.b), D2 = stiffness(other.b);
    const double a11 = dot(main.a, D1), a12 = dot(main.a, D2), a21 = dot(other.a, D1), a22 = dot(other.a, D2);
    const double f1 = dot(main.a, trial) - k_, f2 = dot(other.a, trial) - k_;
    const double det = a11 * a22 - a12 * a21;
    const double l1 = (f1 * a22 - f2 * a12) / det, l2 = (a11 * f2 - a21 * f1) / det;
    for (int i = 0; i < 3; ++i) out[i] = trial[i] - l1 * D1[i] - l2 * D2[i];
    return l1 >= 0 && l2 >= 0 && out[0] >= out[1] - tol && out[1] >= out[2] - tol;
  }

  // With the tension cut-off (Rankine planes s_i <= t, associated): the
  // active set among the cone's three planes (the main one and its two
  // neighbours across the edges) and the three Rankine planes, by trying the
  // sets of one to three surfaces in turn and keeping the first that meets
  // the Kuhn-Tucker conditions (multipliers >= 0, every surface satisfied,
  // the order kept). At most 41 small linear solves, only for the points
  // the cut-off reaches.
  Returned with_cut_off(const Vec3& trial, double tol) const {
    const double t = tension_;
    for (int size = 1; size <= 3; ++size) {
      for (int mask = 1; mask < (1 << surface_count); ++mask) {
        if (__builtin_popcount(mask) != size) continue;
        int ids[3], n = 0;
        for (int i = 0; i < surface_count; ++i)
          if (mask & (1 << i)) ids[n++] = i;
        // Solve sum_j (a_i . D b_j) dl_j = f_i(trial) for the active i.
        double A[3][3] = {}, rhs[3] = {}, dl[3] = {};
        Vec3 Db[3];
        for (int j = 0; j < n; ++j) Db[j] = stiffness(surfaces_[ids[j]].b);
        for (int i = 0; i < n; ++i) {
          rhs[i] = dot(surfaces_[ids[i]].a, trial) - surfaces_[ids[i]].limit;
          for (int j = 0; j < n; ++j) A[i][j] = dot(surfaces_[ids[i]].a, Db[j]);
        }
        if (!solve(n, A, rhs, dl)) continue;
        bool ok = true;
        for (int j = 0; j < n; ++j) ok = ok && dl[j] >= 0;
        if (!ok) continue;
        Vec3 s = trial;
        for (int j = 0; j < n; ++j)
          for (int c = 0; c < 3; ++c) s[c] -= dl[j] * Db[j][c];
        ok = s[0] >= s[1] - tol && s[1] >= s[2] - tol && yield(s) <= tol && s[0] <= t + tol;
        if (ok) return {s, n, {ids[0], n > 1 ? ids[1] : 0, n > 2 ? ids[2] : 0}};
      }
    }
    // Not reached for psi <= phi; the most tensile admissible state.
    return {{t, t, t}, 3, {cut_off_1, cut_off_2, cut_off_3}};
  }

  // Gaussian elimination with partial pivoting, n <= 3; false if singular.
  static bool solve(int n, double A[3][3], double b[3], double x[3]) {
    for (int c = 0; c < n; ++c) {
      int pivot = c;
      for (int r = c + 1; r < n; ++r)
        if (std::abs(A[r][c]) > std::abs(A[pivot][c])) pivot = r;
      if (std::abs(A[pivot][c]) < 1e-300) return false;
      std::swap(A[c], A[pivot]);
      std::swap(b[c], b[pivot]);
      for (int r = c + 1; r < n; ++r) {
        const double f = A[r][c] / A[c][c];
        for (int k = c; k < n; ++k) A[r][k] -= f * A[c][k];
        b[r] -= f * b[c];
      }
    }
    for (int r = n - 1; r >= 0; --r) {
      double v = b[r];
      for (int k = r + 1; k < n; ++k) v -= A[r][k] * x[k];
      x[r] = v / A[r][r];
    }
    // A nearly singular pair (two parallel planes) gives huge multipliers: not this set.
    for (int r = 0; r < n; ++r)
      if (!std::isfinite(x[r])) return false;
    return true;
  }

  double G_, lambda_, sin_phi_, k_, tension_, apex_;
  Surface surfaces_[surface_count];
};

}  // namespace suffuse_mohr_coulomb
