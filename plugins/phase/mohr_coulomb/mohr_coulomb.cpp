// phase/mohr_coulomb: elastic-perfectly plastic Mohr-Coulomb skeleton with a
// non-associated flow rule (dilatancy angle) and an optional tension cut-off,
// integrated with the exact return mapping in principal stresses of Clausen,
// Damkilde & Andersen (2006, 2007): return to the yield plane, to one of its
// two edges (triaxial compression and extension meridians) or to the apex.
// Elasticity is isotropic with the Jaumann rate, as phase/linear_elastic.
//
// Signs: the core's, tension positive. Principal stresses are sorted
// s1 >= s2 >= s3 (s1 the least compressive). The yield function is
//   f = (s1 - s3) + (s1 + s3) sin(phi) - 2 c cos(phi) <= 0
// and the plastic potential g the same with psi for phi. The apex, where
// every edge meets, is the isotropic tension c cot(phi). With a tension
// cut-off s_i <= t the return is an active set of the cone's planes and the
// cut-off's (with_cut_off).
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <suffuse/plugin.hpp>
#include <suffuse/tensor.hpp>

namespace {

using Vec3 = std::array<double, 3>;

double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

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

constexpr double degree = 3.14159265358979323846 / 180;

class MohrCoulomb final : public suffuse::Phase {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("density").with_unit("kg/m^3").above(0).doc("Mass density (of the grains in a saturated body)");
    s.number("youngs_modulus").with_unit("Pa").above(0).doc("Young's modulus E");
    s.number("poisson_ratio").with_unit("-").above(-1).below(0.5).fallback(0.3).doc("Poisson's ratio nu");
    s.number("friction_angle").with_unit("deg").at_least(0).below(90).doc("Friction angle phi");
    s.number("cohesion").with_unit("Pa").at_least(0).fallback(0.0).doc("Cohesion c");
    s.number("dilatancy_angle").with_unit("deg").at_least(0).below(90).fallback(0.0).doc(
        "Dilatancy angle psi of the plastic potential (psi = phi: associated flow)");
    s.number("tensile_strength").with_unit("Pa").at_least(0).may_be_absent().doc(
        "Tension cut-off: no principal (effective) stress above it. Absent: the apex of the cone, c cot(phi); "
        "required for phi = 0");
    return s;
  }

  static std::vector<suffuse::ParameterIssue> check(const suffuse::Parameters& p, int) {
    std::vector<suffuse::ParameterIssue> issues;
    const double phi = p.number("friction_angle"), psi = p.number("dilatancy_angle"), c = p.number("cohesion");
    if (psi > phi)
      issues.push_back({"dilatancy_angle", "dilatancy above friction", "at most friction_angle = " + std::to_string(phi),
                        std::to_string(psi)});
    if (phi == 0 && c == 0)
      issues.push_back({"cohesion", "no strength at all", "cohesion > 0 when friction_angle is 0", "0"});
    if (phi == 0 && !p.has("tensile_strength"))
      issues.push_back({"tensile_strength", "no tension limit", "a tensile_strength when friction_angle is 0 (Tresca)",
                        "nothing"});
    if (p.has("tensile_strength") && phi > 0) {
      const double apex = c * std::cos(phi * degree) / std::sin(phi * degree);
      if (p.number("tensile_strength") > apex)
        issues.push_back({"tensile_strength", "cut-off beyond the apex",
                          "at most c cot(phi) = " + std::to_string(apex) + " Pa",
                          std::to_string(p.number("tensile_strength"))});
    }
    return issues;
  }

  explicit MohrCoulomb(const suffuse::PluginArgs& args)
      : rho_(args.params.number("density")),
        nu_(args.params.number("poisson_ratio")),
        E_(args.params.number("youngs_modulus")),
        G_(E_ / (2 * (1 + nu_))),
        lambda_(E_ * nu_ / ((1 + nu_) * (1 - 2 * nu_))),
        cohesion_(args.params.number("cohesion")),
        phi_(args.params.number("friction_angle") * degree),
        psi_(args.params.number("dilatancy_angle") * degree),
        tensile_strength_(args.params.maybe_number("tensile_strength")),
        return_(return_for(1.0)) {}

  double density() const override { return rho_; }
  double p_wave_modulus() const override { return lambda_ + 2 * G_; }

  void add_fields(suffuse::PointSet& points) override {
    using K = suffuse::FieldKind;
    plastic_strain_ =
        points.add_field({"plastic_strain", K::SymmetricTensor, "-", "accumulated plastic strain (Mohr-Coulomb)", true});
    yielding_ = points.add_field({"yielding", K::Scalar, "-", "1 where the last step was plastic, else 0", true});
    trial_stress_ = points.add_field(
        {"mohr_coulomb_trial_stress", K::SymmetricTensor, "Pa", "the elastic trial stress of the last plastic step", false});
  }

  // The consistent tangent of the return each point made in its last update
  // (Clausen, Damkilde & Andersen 2007; the spin of the principal axes as in
  // de Souza Neto, Peric & Owen 2008, section A.5): with it the quasi-static
  // Newton iterations converge quadratically where points yield. It is not
  // symmetric for psi < phi; at the apex it is zero (the core then holds the
  // point's nodes by its creep term).
  bool tangent(const suffuse::StressBatch& batch, std::span<double> stiffness) const override {
    const MohrCoulombReturn reduced = return_for(batch.strength_reduction);
    const MohrCoulombReturn& ret = batch.strength_reduction == 1.0 ? return_ : reduced;
    const suffuse::PointSet& pts = batch.points;
    const double* yielding = pts.data(yielding_);
    const double* trial = pts.data(trial_stress_);
    for (std::size_t p = batch.range.begin; p < batch.range.end; ++p) {
      double* D = stiffness.data() + (p - batch.range.begin) * 36;
      if (yielding[p] == 0)
        suffuse::tensor::isotropic_stiffness(lambda_ + 2 * G_ / 3, G_, D);
      else
        plastic_tangent(ret, suffuse::tensor::to_matrix(trial + p * 6), D);
    }
    return true;
  }
  bool elastic_stiffness(const suffuse::StressBatch& batch, std::span<double> stiffness) const override {
    for (std::size_t p = batch.range.begin; p < batch.range.end; ++p)
      suffuse::tensor::isotropic_stiffness(lambda_ + 2 * G_ / 3, G_, stiffness.data() + (p - batch.range.begin) * 36);
    return true;
  }
  void update_stress(const suffuse::StressBatch& batch) const override {
    const MohrCoulombReturn reduced = return_for(batch.strength_reduction);
    const MohrCoulombReturn& ret = batch.strength_reduction == 1.0 ? return_ : reduced;
    if (batch.points.dim() == 2)
      update<2>(batch, ret);
    else
      update<3>(batch, ret);
  }
  bool reduces_strength() const override { return true; }

 private:
  // The return of the strength divided by F (a strength reduction; F = 1:
  // the material's own): c / F, tan(phi) / F and tan(psi) / F (the
  // dilatancy reduced alike, so it stays at most the friction), a tensile
  // strength t / F. The cone's apex, (c / F) / tan(phi_F) = c cot(phi),
  // does not move, so t / F stays below it.
  MohrCoulombReturn return_for(double F) const {
    const bool own = F == 1.0;  // exactly the given angles (atan(tan(x)) may differ from x in its last bit)
    const double phi = own ? phi_ : std::atan(std::tan(phi_) / F), psi = own ? psi_ : std::atan(std::tan(psi_) / F);
    const double c = cohesion_ / F;
    double tension = std::numeric_limits<double>::infinity();  // Tresca without a cut-off is refused
    if (tensile_strength_)
      tension = *tensile_strength_ / F;
    else if (phi > 0)
      tension = c * std::cos(phi) / std::sin(phi);
    return MohrCoulombReturn(G_, lambda_, phi, c, psi, tension);
  }

  // The principal stresses of s, sorted s1 >= s2 >= s3, and their axes (column a for s_a).
  struct PrincipalAxes {
    Vec3 values;
    Eigen::Matrix3d axes;
    double tolerance;  // of the return, relative to the stress and the cohesion
  };
  // A plane-strain stress (no out-of-plane shear, as in every 2D run) has
  // the out-of-plane axis as one principal axis and the in-plane pair in
  // closed form: one square root, where Eigen's 3x3 solver takes an atan2, a
  // cos and a sin, and cross products for the axes. That solver was most of
  // the levee's stress stage, at every point and step, yielding or not.
  // The in-plane principal stresses m +- r (centre and radius of Mohr's
  // circle, h the half difference of s_xx and s_yy), if s is such a stress
  // and they and s_zz are finite; anything else (a NaN, an overflow) goes
  // through Eigen's solver, as every stress did before, and stays NaN.
  static bool mohr_circle(const suffuse::tensor::Matrix& s, double& m, double& h, double& r) {
    if (!(s[0][2] == 0 && s[1][2] == 0)) return false;
    m = 0.5 * (s[0][0] + s[1][1]), h = 0.5 * (s[0][0] - s[1][1]);
    r = std::sqrt(h * h + s[0][1] * s[0][1]);
    return std::isfinite(m) && std::isfinite(r) && std::isfinite(s[2][2]);
  }
  // {hi, lo, zz} sorted descending: order[k] is the index of s_k among them.
  static std::array<int, 3> descending(const Vec3& v) {
    std::array<int, 3> order{0, 1, 2};  // v[0] >= v[1] always (hi, lo)
    if (v[2] > v[0])
      order = {2, 0, 1};
    else if (v[2] > v[1])
      order = {0, 2, 1};
    return order;
  }
  static Eigen::Matrix3d to_eigen(const suffuse::tensor::Matrix& s) {
    Eigen::Matrix3d m;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m(i, j) = s[i][j];
    return m;
  }
  double tolerance_of(const Vec3& values) const {
    return 1e-12 * (std::abs(values[0]) + std::abs(values[2]) + cohesion_);
  }
  // The principal stresses alone, sorted: all an elastic step needs.
  Vec3 principal_values(const suffuse::tensor::Matrix& s) const {
    double m, h, r;
    if (!mohr_circle(s, m, h, r)) {
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
      eig.computeDirect(to_eigen(s), Eigen::EigenvaluesOnly);  // the values principal_axes finds
      return {eig.eigenvalues()(2), eig.eigenvalues()(1), eig.eigenvalues()(0)};
    }
    const Vec3 v{m + r, m - r, s[2][2]};
    const auto k = descending(v);
    return {v[k[0]], v[k[1]], v[k[2]]};
  }
  PrincipalAxes principal_axes(const suffuse::tensor::Matrix& s) const {
    PrincipalAxes out;
    double m, h, r;
    if (mohr_circle(s, m, h, r)) {
      const Vec3 v{m + r, m - r, s[2][2]};
      // The major in-plane axis from the better conditioned row of (s - hi I)
      // x = 0 (its larger component is at least r), scaled by that component
      // first so that a tiny shear does not underflow its length.
      const double c = s[0][1];
      double x = h >= 0 ? h + r : c, y = h >= 0 ? c : r - h;
      const double larger = std::max(std::abs(x), std::abs(y));
      if (larger > 0) {
        x /= larger, y /= larger;
        const double length = std::sqrt(x * x + y * y);
        x /= length, y /= length;
      } else {
        x = 1, y = 0;  // isotropic in the plane: any pair of axes
      }
      Eigen::Matrix3d axes;
      axes << x, -y, 0, y, x, 0, 0, 0, 1;  // columns: hi, lo, zz
      const auto k = descending(v);
      for (int a = 0; a < 3; ++a) out.values[a] = v[k[a]], out.axes.col(a) = axes.col(k[a]);
    } else {
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
      eig.computeDirect(to_eigen(s));  // ascending eigenvalues
      out.values = {eig.eigenvalues()(2), eig.eigenvalues()(1), eig.eigenvalues()(0)};
      out.axes = eig.eigenvectors().rowwise().reverse();
    }
    out.tolerance = tolerance_of(out.values);
    return out;
  }

  template <int D>
  void update(const suffuse::StressBatch& batch, const MohrCoulombReturn& ret) const {
    namespace t = suffuse::tensor;
    suffuse::PointSet& pts = batch.points;
    double* stress = pts.data(pts.core().stress);
    double* plastic = pts.data(plastic_strain_);
    double* yielding = pts.data(yielding_);
    double* trial_stress = pts.data(trial_stress_);
    const suffuse::StepIncrements<D> increments(batch);
    for (std::size_t p = batch.range.begin; p < batch.range.end; ++p) {
      const auto [d, w] = increments(p);
      double* s6 = stress + p * 6;
      const t::Matrix trial = t::jaumann_elastic_increment(t::to_matrix(s6), d, w, G_, lambda_);
      const Vec3 values = principal_values(trial);
      if (ret.admissible(values, tolerance_of(values))) {
        t::store(trial, s6);
        yielding[p] = 0;
        continue;
      }
      const PrincipalAxes pa = principal_axes(trial);
      const Vec3& principal = pa.values;
      t::store(trial, trial_stress + p * 6);
      const Vec3 s = ret(principal, pa.tolerance).stress;
      // Back to the axes of the trial stress; the plastic strain is D^-1 of the stress removed.
      const Vec3 removed = {principal[0] - s[0], principal[1] - s[1], principal[2] - s[2]};
      const double tr = removed[0] + removed[1] + removed[2];
      Vec3 de;
      for (int i = 0; i < 3; ++i) de[i] = ((1 + nu_) * removed[i] - nu_ * tr) / E_;
      t::Matrix next{}, dep{};
      for (int a = 0; a < 3; ++a) {
        const auto v = pa.axes.col(a);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            next[i][j] += s[a] * v(i) * v(j);
            dep[i][j] += de[a] * v(i) * v(j);
          }
      }
      t::store(next, s6);
      double* ep = plastic + p * 6;
      const t::Voigt add = t::to_voigt(dep);
      for (int c = 0; c < 6; ++c) ep[c] += add[c];
      yielding[p] = 1;
    }
  }

  // The derivative of the returned stress by the strain increment, 6x6 in
  // the form Phase::tangent returns, from the trial stress. In the principal
  // axes the normal components follow principal_tangent; a shear component
  // ab turns the axes, and the stress follows with the modulus
  // G (s_a - s_b) / (s_a^trial - s_b^trial) (its limit where the trial's
  // s_a = s_b).
  void plastic_tangent(const MohrCoulombReturn& ret, const suffuse::tensor::Matrix& trial, double* D) const {
    const PrincipalAxes pa = principal_axes(trial);
    const auto r = ret(pa.values, pa.tolerance);
    const std::array<double, 9> Dp = ret.principal_tangent(r);
    double shear[3][3] = {};
    for (int a = 0; a < 3; ++a)
      for (int b = a + 1; b < 3; ++b) {
        const double gap = pa.values[a] - pa.values[b];
        shear[a][b] = shear[b][a] = gap > 1e-9 * (std::abs(pa.values[a]) + std::abs(pa.values[b]) + cohesion_)
                                        ? G_ * (r.stress[a] - r.stress[b]) / gap
                                        : (Dp[a * 3 + a] - Dp[a * 3 + b] - Dp[b * 3 + a] + Dp[b * 3 + b]) / 4;
      }
    static constexpr int first[6] = {0, 1, 2, 1, 0, 0}, second[6] = {0, 1, 2, 2, 2, 1};
    const Eigen::Matrix3d& v = pa.axes;
    for (int c = 0; c < 6; ++c) {
      // A unit engineering strain of component c, in the principal axes.
      const int i = first[c], j = second[c];
      Eigen::Matrix3d e;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) e(a, b) = i == j ? v(i, a) * v(i, b) : 0.5 * (v(i, a) * v(j, b) + v(j, a) * v(i, b));
      Eigen::Matrix3d ds;  // the stress it gives, in the principal axes
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          ds(a, b) = a == b ? Dp[a * 3] * e(0, 0) + Dp[a * 3 + 1] * e(1, 1) + Dp[a * 3 + 2] * e(2, 2)
                            : 2 * shear[a][b] * e(a, b);
      const Eigen::Matrix3d global = v * ds * v.transpose();
      for (int row = 0; row < 6; ++row) D[row * 6 + c] = global(first[row], second[row]);
    }
  }

  double rho_, nu_, E_, G_, lambda_, cohesion_, phi_, psi_;
  std::optional<double> tensile_strength_;
  MohrCoulombReturn return_;
  suffuse::FieldId plastic_strain_ = 0, yielding_ = 0, trial_stress_ = 0;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::Phase, MohrCoulomb>(
      "phase/mohr_coulomb",
      "Elastic-perfectly plastic Mohr-Coulomb with dilatancy and tension cut-off, exact return in principal stresses");
}
