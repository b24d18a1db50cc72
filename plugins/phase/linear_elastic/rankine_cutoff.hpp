// Rankine's tension cut-off with no tensile strength for phase/linear_elastic's
// "separation": "planes": the return to the closest tension-free stress and its
// tangent: one idea, in a file of its own beside the plugin's elasticity.
#pragma once

#include <suffuse/tensor.hpp>

namespace suffuse::linear_elastic {

struct Lame {
  double lambda, G;
};

// The return mapping of perfect plasticity in principal stresses
// (associative, isotropic elasticity; de Souza Neto, Peric & Owen 2008,
// chapter 8): the trial stress goes to the closest tension-free state in the
// energy norm. With one principal stress s_A tensile, s_A becomes zero and the
// plastic strain d_gamma = s_A / (lambda + 2G) along it takes lambda d_gamma
// from the others (the lateral effect of the strain that separated the
// grains); with two, both zero (the edge); with all three, exactly no stress
// (the apex). The principal directions are the trial's.
// Returns the number of separated directions, with the stress in `trial` and
// the plastic multiplier in `multiplier`.
int rankine_return(const Lame& elastic, tensor::Matrix& trial, double& multiplier);

// The tangent of the return at a returned stress s6 (Voigt xx yy zz yz xz xy),
// overwriting D (6x6, row-major) where a principal value is at zero: the
// normal stiffness with the separated directions' stresses held at zero, and
// the shear across a separated plane the return's share (de Souza Neto et al.
// 2008, appendix A). D is left as it is (Hooke's) where no principal value is
// at zero.
void rankine_tangent(const Lame& elastic, const double* s6, double multiplier, double* D);

}  // namespace suffuse::linear_elastic
