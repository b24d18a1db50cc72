// phase/linear_elastic: isotropic Hooke's law, small-strain incremental form,
// with the Jaumann rate so that a rigid rotation does not create stress.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <suffuse/plugin.hpp>

#include "rankine_cutoff.hpp"

namespace {

class LinearElastic final : public suffuse::Phase {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("density").with_unit("kg/m^3").above(0).doc("Mass density");
    s.number("youngs_modulus").with_unit("Pa").above(0).doc("Young's modulus E");
    s.number("poisson_ratio").with_unit("-").above(-1).below(0.5).fallback(0.0).doc("Poisson's ratio nu");
    s.boolean("tension_cutoff").fallback(false).doc(
        "Cohesionless skeleton: no principal (effective) stress may be tensile, so the grains can separate "
        "(heave, fluidisation); how, says separation");
    s.choice("separation", {"point", "planes"}).fallback(std::string("point")).doc(
        "With tension_cutoff: point, a point whose largest principal stress turns tensile carries no stress at "
        "all; planes, Rankine's cut-off (a perfectly plastic return to the closest tension-free stress): the "
        "grains separate across the planes that would be pulled and keep the other stresses, less the lateral "
        "effect of the separation, and nothing only where pulled in every direction. planes is continuous in "
        "the strain, so quasi-static runs converge through a heave where point can stall");
    return s;
  }

  explicit LinearElastic(const suffuse::PluginArgs& args)
      : rho_(args.params.number("density")),
        tension_cutoff_(args.params.boolean("tension_cutoff")),
        planes_(tension_cutoff_ && args.params.string("separation") == "planes") {
    const double E = args.params.number("youngs_modulus"), nu = args.params.number("poisson_ratio");
    G_ = E / (2 * (1 + nu));
    lambda_ = E * nu / ((1 + nu) * (1 - 2 * nu));
  }

  void add_fields(suffuse::PointSet& points) override {
    if (!planes_) return;
    separated_ = points.add_field({suffuse::coupling::separated_directions, suffuse::FieldKind::Scalar, "-",
                                   "principal directions in which the grains separated (tension cut-off), 0 to 3",
                                   true});
    multiplier_ = points.add_field({"cutoff_multiplier", suffuse::FieldKind::Scalar, "-",
                                    "the tension cut-off's plastic multiplier of the last step (its tangent)", false});
  }

  double density() const override { return rho_; }
  double p_wave_modulus() const override { return lambda_ + 2 * G_; }

  // The tangent: Hooke's law (the stress update adds only the Jaumann
  // rotation, which a quasi-static step leaves to the iterations); with the
  // tension cut-off, at a stress with principal values at zero, the
  // elastoplastic tangent of the return (rankine_tangent); none for a point
  // separated in every direction.
  bool tangent(const suffuse::StressBatch& batch, std::span<double> stiffness) const override {
    const double* stress = batch.points.data(batch.points.core().stress);
    for (std::size_t p = batch.range.begin; p < batch.range.end; ++p) {
      double* D = stiffness.data() + (p - batch.range.begin) * 36;
      const double* s6 = stress + p * 6;
      const bool separated = tension_cutoff_ && s6[0] == 0 && s6[1] == 0 && s6[2] == 0 && s6[3] == 0 &&
                             s6[4] == 0 && s6[5] == 0;
      suffuse::tensor::isotropic_stiffness(separated ? 0.0 : lambda_ + 2 * G_ / 3, separated ? 0.0 : G_, D);
      if (planes_ && !separated && batch.points.data(separated_)[p] > 0)
        suffuse::linear_elastic::rankine_tangent({lambda_, G_}, s6, batch.points.data(multiplier_)[p], D);
    }
    return true;
  }
  void update_stress(const suffuse::StressBatch& batch) const override {
    if (batch.points.dim() == 2)
      planes_ ? update<2, true>(batch) : update<2, false>(batch);
    else
      planes_ ? update<3, true>(batch) : update<3, false>(batch);
  }

 private:
  // "planes" gets a loop of its own: it writes two more fields per point,
  // which the other modes' loop need not test for.
  template <int D, bool Planes>
  void update(const suffuse::StressBatch& batch) const {
    double* stress = batch.points.data(batch.points.core().stress);
    double* separated = Planes ? batch.points.data(separated_) : nullptr;
    double* multiplier = Planes ? batch.points.data(multiplier_) : nullptr;
    // Locals: stores through a double* could alias *this's moduli for the
    // compiler (not measured to matter).
    const suffuse::linear_elastic::Lame elastic{lambda_, G_};
    const bool tension_cutoff = tension_cutoff_;
    const suffuse::StepIncrements<D> increments(batch);
    for (std::size_t p = batch.range.begin; p < batch.range.end; ++p) {
      // Full 3x3 increments; out-of-plane components stay zero in 2D (plane strain).
      const auto [d, w] = increments(p);
      double* s6 = stress + p * 6;
      suffuse::tensor::Matrix ns;
      if constexpr (D == 2)
        ns = plane_jaumann_elastic_increment(elastic, s6, d, w[0][1]);
      else
        ns = suffuse::tensor::jaumann_elastic_increment(suffuse::tensor::to_matrix(s6), d, w, elastic.G,
                                                        elastic.lambda);
      if constexpr (Planes) {
        multiplier[p] = 0;
        separated[p] = has_tension(ns) ? suffuse::linear_elastic::rankine_return(elastic, ns, multiplier[p]) : 0;
      } else if (tension_cutoff && has_tension(ns)) {
        // Element by element: with `ns = {}` g++ 12 compiled the whole loop
        // through the stack, a fifth slower even where no point separates.
        for (auto& row : ns)
          for (double& v : row) v = 0;
      }
      suffuse::tensor::store(ns, s6);
    }
  }

  // jaumann_elastic_increment in 2D, where the spin has the one component
  // w01 = -w10 = omega: the rotation w s - s w, written out, is 2 omega s01 on
  // xx, -2 omega s01 on yy, omega (s11 - s00) on xy, omega s12 on xz and
  // -omega s02 on yz (the strain increment may have out-of-plane parts, from
  // an eigenstrain). A quarter of the general form's arithmetic.
  static suffuse::tensor::Matrix plane_jaumann_elastic_increment(const suffuse::linear_elastic::Lame& elastic,
                                                                 const double* s6, const suffuse::tensor::Matrix& d,
                                                                 double omega) {
    const double xx = s6[0], yy = s6[1], zz = s6[2], yz = s6[3], xz = s6[4], xy = s6[5];
    const double volumetric = elastic.lambda * (d[0][0] + d[1][1] + d[2][2]), G2 = 2 * elastic.G;
    const double shear_rotation = 2 * omega * xy;
    const double nxx = xx + G2 * d[0][0] + volumetric + shear_rotation;
    const double nyy = yy + G2 * d[1][1] + volumetric - shear_rotation;
    const double nzz = zz + G2 * d[2][2] + volumetric;
    const double nxy = xy + G2 * d[0][1] + omega * (yy - xx);
    const double nxz = xz + G2 * d[0][2] + omega * yz;
    const double nyz = yz + G2 * d[1][2] - omega * xz;
    return {{{nxx, nxy, nxz}, {nxy, nyy, nyz}, {nxz, nyz, nzz}}};
  }

  // True when the largest principal stress is positive, that is when s is
  // not negative semi-definite: some principal minor of -s is negative.
  // Without an eigensolver where that is exact in floating point too (an
  // eigensolver per point and step cost a fifth of the default column's step):
  // - a positive diagonal term: the largest principal stress is at least it;
  // - plane strain (no xz, yz shear): szz is principal, the rest a 2x2 block,
  //   whose determinant has the round-off of the stresses' scale;
  // - otherwise the 3x3 minors, and the eigensolver only where the
  //   determinant is within its round-off of zero (two principal stresses
  //   near zero: its error then exceeds their product).
  static bool has_tension(const suffuse::tensor::Matrix& s) {
    if (s[0][0] > 0 || s[1][1] > 0 || s[2][2] > 0) return true;
    const double m01 = s[0][0] * s[1][1] - s[0][1] * s[0][1];
    if (s[0][2] == 0 && s[1][2] == 0) return m01 < 0;
    const double m02 = s[0][0] * s[2][2] - s[0][2] * s[0][2];
    const double m12 = s[1][1] * s[2][2] - s[1][2] * s[1][2];
    if (m01 < 0 || m02 < 0 || m12 < 0) return true;
    // det(-s) = -det(s) >= 0 for a negative semi-definite s.
    const double det = s[0][0] * m12 - s[0][1] * (s[0][1] * s[2][2] - s[1][2] * s[0][2]) +
                       s[0][2] * (s[0][1] * s[1][2] - s[1][1] * s[0][2]);
    double scale = 0;
    for (const auto& row : s)
      for (double v : row) scale = std::max(scale, std::abs(v));
    if (std::abs(det) > 1e-12 * scale * scale * scale) return det > 0;
    Eigen::Matrix3d m;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m(i, j) = s[i][j];
    return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(m, Eigen::EigenvaluesOnly).eigenvalues()(2) > 0;
  }

  double rho_;
  bool tension_cutoff_, planes_;
  suffuse::FieldId separated_ = 0, multiplier_ = 0;
  double G_, lambda_;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::Phase, LinearElastic>(
      "phase/linear_elastic",
      "Isotropic linear elasticity, small-strain incremental, Jaumann-rotated stress");
}
