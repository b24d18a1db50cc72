#include "quasi_static/quasi_static.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include "parallel/executor.hpp"
#include "quasi_static/quasi_static_linear.hpp"
#include "mpm/solid_kernels.hpp"
#include "suffuse/error.hpp"
#include "suffuse/liquid.hpp"
#include "suffuse/tensor.hpp"

namespace suffuse::detail {

QuasiStatic::QuasiStatic(const Scene& scene, Domain& domain, const Materials& materials, SaturatedMixture* mixture,
                         const std::vector<std::unique_ptr<BoundaryCondition>>& bcs, ApplyLoads apply_loads)
    : scene_(scene), d_(domain), materials_(materials), mixture_(mixture), bcs_(bcs),
      apply_loads_(std::move(apply_loads)), linear_(std::make_unique<Linear>()),
      singular_fails_attempt_(scene.failure.has_value()) {
  // On one process too where the scene asks for MUMPS or leaves it to the
  // grid's size (scene.hpp, LinearSolver).
  const LinearSolver solver = scene.quasi_static.linear_solver;
  const bool mumps = solver == LinearSolver::mumps || (solver == LinearSolver::automatic && built_with_petsc() &&
                                                       d_.grid.node_count() >= mumps_from_grid_nodes);
  if (d_.comm.parallel() || mumps)
    linear_->distributed = make_distributed_system(d_.comm, "the quasi-static step's solve", "suffuse_qs_");
  const std::size_t nn = d_.grid.node_count();
  const int dim = d_.dim();
  probe_.resize(nn, dim, mixture_ != nullptr);
  for (auto* v : {&node_mass_, &node_pore_, &node_volume_, &p_}) v->assign(nn, 0.0);
  du_.assign(nn * dim, 0.0);
  f_ext_.assign(nn * dim, 0.0);
  for (std::size_t m = 0; m < scene.materials.size(); ++m) {
    modulus_.push_back(materials.phase(m).p_wave_modulus());
    drainage_.push_back(scene.materials[m].phreatic ? std::optional<Drainage>(*scene.materials[m].phreatic)
                                                    : std::nullopt);
  }
  phreatic_ = mixture_ && scene.phreatic();
  if (phreatic_) seepage_closed_.assign(nn, 0);
  std::size_t cells = 1;
  for (int a = 0; a < dim; ++a) cells *= static_cast<std::size_t>(d_.grid.cells()[a]);
  cell_count_.assign(cells, 0.0);
}

QuasiStatic::~QuasiStatic() = default;

void QuasiStatic::save_state(std::vector<std::vector<double>>& into) const {
  const auto& ids = materials_.stress_state_fields();
  into.resize(ids.size());
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const auto v = d_.points.values(ids[k]);
    into[k].assign(v.begin(), v.end());
  }
}

void QuasiStatic::restore_state(const std::vector<std::vector<double>>& from) {
  const auto& ids = materials_.stress_state_fields();
  for (std::size_t k = 0; k < ids.size(); ++k) std::copy(from[k].begin(), from[k].end(), d_.points.data(ids[k]));
}

// The stresses of the current increments (each phase's own update from the
// state at the start of the step) and the out-of-balance forces and
// volumes; returns the norm of the forces at the free components.
double QuasiStatic::evaluate(double dt) {
  const int dim = d_.dim();
  const std::size_t nn = d_.grid.node_count();
  for (std::size_t k = 0; k < du_.size(); ++k) d_.nodes.velocity[k] = du_[k] / dt;
  d_.periodic.copy_to_images(d_.nodes.velocity, dim);  // (the compact supports reach them)
  d_.update_velocity_gradient(dt);
  materials_.update_stress_with_imposed_eigenstrain(d_, dt, reduction_.value_or(1.0));

  PointSet& pts = d_.points;
  const auto& c = pts.core();
  const ExpandedSupports& s = d_.expanded_shape();
  const double* V = pts.data(c.volume);
  const double* sigma = pts.data(c.stress);
  const double* n = mixture_ ? pts.data(mixture_->fields().porosity) : nullptr;
  const double* KL = mixture_ ? pts.data(mixture_->fields().bulk_modulus) : nullptr;
  const double* K = mixture_ ? pts.data(mixture_->fields().conductivity) : nullptr;
  const double* rho_w = mixture_ ? pts.data(mixture_->fields().water_density) : nullptr;
  std::vector<double>& f_int = f_int_;
  f_int.assign(nn * dim, 0.0);
  std::vector<double>& r_p = r_p_;
  r_p = b_p_;  // every process's sum: the others add their points' terms only
  if (!d_.comm.root()) std::fill(r_p.begin(), r_p.end(), 0.0);
  point_pressure_.assign(pts.size(), 0.0);
  const double* material = pts.data(c.material_id);
  std::vector<double>& water_terms = water_terms_;  // phreatic scenes: per node, the sum of the sizes of its pressure equation's terms
  if (phreatic_) {
    water_terms.assign(nn, 0.0);
    coupling_.assign(pts.size(), 1.0);
    saturation_.assign(pts.size(), 1.0);
    relative_.assign(pts.size(), 1.0);
    capacity_.assign(pts.size(), 0.0);  // a saturated point's n / K_L, set below where it has pores
    drift_.assign(pts.size() * 3, 0.0);
  }
  for (std::size_t p = 0; p < pts.size(); ++p) {
    const bool wet = n && n[p] > 0;
    double pp = 0, grad_p[3] = {0, 0, 0}, div_u = 0;
    if (wet)
      for (int a = 0; a < s.npp; ++a) {
        const std::size_t q = p * s.npp + a;
        const std::int64_t I = s.ids[q];
        pp += s.weights[q] * p_[I];
        for (int i = 0; i < dim; ++i) {
          grad_p[i] += s.gradients[q * dim + i] * p_[I];
          div_u += s.gradients[q * dim + i] * du_[I * dim + i];
        }
      }
    point_pressure_[p] = pp;
    const std::optional<Drainage>* drains =
        phreatic_ && wet ? &drainage_[static_cast<std::size_t>(material[p])] : nullptr;
    if (drains && *drains) {
      add_drained_point_terms(**drains, p, pp, grad_p, div_u, dt, f_int, r_p, water_terms);
      continue;
    }
    if (phreatic_ && wet) capacity_[p] = n[p] / KL[p];
    const double* sp = sigma + p * 6;
    for (int a = 0; a < s.npp; ++a) {
      const std::size_t q = p * s.npp + a;
      const std::int64_t I = s.ids[q];
      const double* gN = &s.gradients[q * dim];
      for (int i = 0; i < dim; ++i) {
        double f = -V[p] * pp * gN[i];  // total stress sigma' - p I
        for (int j = 0; j < dim; ++j) f += V[p] * sp[tensor::voigt_index(i, j)] * gN[j];
        f_int[I * dim + i] += f;
      }
      if (!wet) continue;
      const double k = K[p] / (rho_w[p] * reference_gravity);
      double flow = 0;
      for (int i = 0; i < dim; ++i) flow += gN[i] * grad_p[i];
      const double stored = s.weights[q] * V[p] * (n[p] / KL[p] * pp + div_u), flowing = dt * V[p] * k * flow;
      r_p[I] -= stored + flowing;
      if (phreatic_) water_terms[I] += std::abs(stored) + std::abs(flowing);
    }
  }
  sum_over_processes(f_int);
  if (mixture_) sum_over_processes(r_p);
  if (phreatic_) sum_over_processes(water_terms);
  double r2 = 0, f2 = 0, i2 = 0, a2 = 0;
  for (std::size_t I = 0; I < nn; ++I)
    for (int i = 0; i < dim; ++i) {
      const std::size_t k = I * dim + i;
      if (node_mass_[I] <= 0) continue;
      f2 += f_ext_[k] * f_ext_[k];
      i2 += f_int[k] * f_int[k];
      if (u_dof_[k] < 0) continue;
      double r = f_ext_[k] - f_int[k] - creep_[k] * du_[k];
      if (!inertia_.empty()) {
        const double inertial = inertia_[k] * (du_[k] - inertia_target_[k]);
        r -= inertial;
        a2 += inertial * inertial;  // a body in flight: its inertia is the force acting
      }
      residual_[static_cast<std::size_t>(u_dof_[k])] = r;
      r2 += r * r;
    }
  for (std::size_t I = 0; I < nn; ++I)
    if (p_dof_[I] >= 0 && (!surface_node_[I] || (phreatic_ && seepage_closed_[I])))
      residual_[static_cast<std::size_t>(p_dof_[I])] = -r_p[I];
  for (const Extrapolated& e : extrapolated_)
    residual_[static_cast<std::size_t>(p_dof_[e.node])] -= e.factor * r_p[e.node];
  if (phreatic_) {  // the water balance converges with the forces (merged equations counted once)
    double w2 = 0, s2 = 0;
    for (std::size_t e = displacement_equations_; e < equations_; ++e) w2 += residual_[e] * residual_[e];
    for (std::size_t I = 0; I < nn; ++I)
      if (p_dof_[I] >= 0) s2 += water_terms[I] * water_terms[I];
    water_norm_ = std::sqrt(w2);
    water_scale_ = std::sqrt(s2);
  }
  force_scale_ = std::sqrt(std::max({f2, i2, a2}));
  return std::sqrt(r2);
}

// Newton iterations on the true stresses, the matrix from the phases'
// tangents at each iterate (a cohesionless point that separates has none).
std::optional<int> QuasiStatic::solve(double time, double dt) {
  failure_.clear();
  int iterations = 0;
  attempted_iterations_ = 0;
  if (!reduction_) equilibrium_p_ = accepted_p_;  // not a rejected attempt's
  // Phreatic scenes solve the step again while its seepage faces change
  // (settle_seepage_faces), from the same start, at most this many times.
  constexpr int max_seepage_rounds = 8;
  for (seepage_rounds_ = 1;; ++seepage_rounds_) {
    if (seepage_rounds_ > 1) restore_state(saved_);
    prepare(time, dt);
    prepare_blocks();
    residual_.assign(equations_, 0.0);
    // The step's eigenstrain, once: every iteration starts from the state
    // with it imposed (a phase's eigenstrain is a function of the state at
    // the step's start, not of the iterate).
    if (seepage_rounds_ == 1) {
      if (materials_.writes_eigenstrain() && !reduction_) {
        save_state(step_start_);
        materials_.impose_eigenstrain(d_, dt);
      }
      save_state(saved_);
    }
    // A later round starts from the last round's equilibrium, not from the
    // step's start: its faces differ at a few nodes whose pressure was near
    // zero, so that equilibrium is within Newton's reach, while the path
    // from the step's start may cross the phreatic surface and the yield
    // surfaces anew (a levee's riverside slope draining as the river falls:
    // a step's second round converged in 7 iterations from the start, its
    // third, one node opened at p = 6.5 Pa, found none in 25; 1 from the
    // second's equilibrium). The stresses are still each phase's update
    // from the step's start: the equilibrium sought is the same.
    if (seepage_rounds_ > 1) warm_start();
    if (!newton(dt, iterations)) break;
    if (!reduction_) keep_equilibrium_pressures();
    if (!phreatic_ || reduction_ || seepage_rounds_ == max_seepage_rounds) return iterations;
    warm_du_ = du_, warm_p_ = p_;
    if (!settle_seepage_faces()) return iterations;
  }
  if (materials_.writes_eigenstrain() && !reduction_) restore_state(step_start_);
  attempted_iterations_ = iterations;
  return std::nullopt;
}

void QuasiStatic::keep_equilibrium_pressures() {
  if (!mixture_) return;
  equilibrium_p_.assign(p_.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t I = 0; I < p_.size(); ++I)
    if (node_pore_[I] > 0) equilibrium_p_[I] = p_[I];
}

// The unknowns at the last seepage round's equilibrium: the increments of
// the nodes with unknowns and the pressures of those with their own (a node
// the round drains keeps the face's pressure; one it closes starts from the
// one it had); the nodes that follow others then follow them.
void QuasiStatic::warm_start() {
  for (std::size_t k = 0; k < u_dof_.size(); ++k)
    if (u_dof_[k] >= 0) du_[k] = warm_du_[k];
  for (std::size_t I = 0; I < p_dof_.size(); ++I)
    if (p_dof_[I] >= 0 && !fixed_pressure_[I]) p_[I] = warm_p_[I];
  follow_inner_nodes();
  follow_tail_nodes();
}

bool QuasiStatic::newton(double dt, int& iterations) {
  // Phreatic scenes: the water balance converges too, to this fraction of
  // its terms. Not to /time/newton_tolerance: the nodes a body barely
  // reaches follow the points (follow_tail_nodes), outside Newton's matrix,
  // which leaves the balance of the nodes beside them near 1e-7 of its terms.
  constexpr double water_tolerance = 1e-6;
  const QuasiStaticControls& control = scene_.quasi_static;
  Linear& L = *linear_;
  Eigen::VectorXd rhs(static_cast<Eigen::Index>(equations_));
  // The size of the residual a line search compares: scaled as the system,
  // so that forces and liquid volumes count alike.
  auto merit = [&] {
    double sum = 0;
    for (std::size_t e = 0; e < equations_; ++e) sum += std::pow(L.scale_of(e) * residual_[e], 2);
    return std::sqrt(sum);
  };
  std::vector<double>& du0 = du_previous_;
  std::vector<double>& p0 = p_previous_;
  // Whether a correction changes no displacement and no pressure by more
  // than round-off of the largest.
  auto round_off = [&](const Eigen::VectorXd& delta) {
    double u = 0, p = 0, du = 0, dp = 0;
    for (std::size_t k = 0; k < u_dof_.size(); ++k) {
      u = std::max(u, std::abs(du_[k]));
      if (u_dof_[k] >= 0) du = std::max(du, std::abs(delta[u_dof_[k]]));
    }
    for (std::size_t I = 0; I < p_dof_.size(); ++I) {
      p = std::max(p, std::abs(p_[I]));
      if (p_dof_[I] >= 0) dp = std::max(dp, std::abs(delta[p_dof_[I]]));
    }
    return u > 0 && du <= 1e-12 * u && dp <= 1e-12 * p;
  };
  bool last_step_is_round_off = false;
  singular_ = false;
  restore_state(saved_);
  double norm = evaluate(dt);
  residuals_.assign(1, force_scale_ > 0 ? norm / force_scale_ : norm);
  // A strength reduction's solve beyond its limit does not diverge: its
  // iterations cycle through the same few returns, the residual never lower.
  // It counts as failed once that many iterations found no new lowest
  // residual (one converging slowly finds one nearly every iteration).
  constexpr int reduction_stall = 12;
  double lowest = std::numeric_limits<double>::infinity();
  int lowest_at = 0;
  for (int iteration = 0;; ++iteration) {
    if (!std::isfinite(norm)) break;
    if (norm < 0.99 * lowest) lowest = norm, lowest_at = iteration;
    if (reduction_ && iteration - lowest_at >= reduction_stall) break;
    // The first evaluation has the old pressures: at least one solve.
    if (iteration > 0 && norm <= control.newton_tolerance * force_scale_ &&
        (!phreatic_ || water_norm_ <= water_tolerance * water_scale_))
      return true;
    // Or the last full Newton step changed the increments by round-off: a
    // body moved only by its constraints (a translation) has no forces to
    // compare the residual with.
    if (iteration > 1 && last_step_is_round_off) return true;
    if (iteration == (reduction_ ? reduction_iterations_ : control.max_iterations)) break;
    ++iterations;
    materials_.tangent(d_, dt, tangent_, reduction_.value_or(1.0));
    assemble(dt);
    for (std::size_t e = 0; e < equations_; ++e) rhs[static_cast<Eigen::Index>(e)] = residual_[e];
    // After the attempt's first iteration the factors of an earlier one
    // precondition GMRES (quasi_static_linear.hpp); factorised if it does
    // not converge with them. Not in a strength reduction's solves: their
    // returns change from iteration to iteration, GMRES failed in nearly
    // every one (399 factorisations in 390 iterations), and skipping it
    // took a fifth off the factor of safety's time.
    std::optional<Eigen::VectorXd> reused;
    if (iteration > 0 && (L.has_factors || L.distributed) && control.reuse_factors && !reduction_) {
      int its = 0;
      reused = L.solve_reusing_factors(rhs, its);
      gmres_iterations_ += static_cast<std::size_t>(its);
    }
    if (!reused && !L.distributed && !factorise_or_throw()) break;
    if (!reused && L.distributed && equations_ > 0) ++factorisations_;  // PETSc sets its preconditioner up anew
    Eigen::VectorXd delta;
    try {
      delta = reused ? std::move(*reused) : L.solve(rhs);
    } catch (const Error& e) {  // PETSc's singular system (the same on every process)
      if (!reduction_ && !singular_fails_attempt_) throw Error(e.what() + std::string(Linear::failing));
      singular_ = true;
      break;  // no equilibrium at that factor, or at that load
    }
    // Backtracking: far from equilibrium a full Newton step on a perfectly
    // plastic skeleton can overshoot onto the wrong side of many returns;
    // halve it until the residual falls (Armijo), at most six times.
    const double before = merit();
    du0 = du_, p0 = p_;
    double alpha = 1;
    for (int halving = 0;; ++halving) {
      for (std::size_t k = 0; k < u_dof_.size(); ++k)
        if (u_dof_[k] >= 0) du_[k] = du0[k] + alpha * delta[u_dof_[k]];
      for (std::size_t I = 0; I < p_dof_.size(); ++I)
        if (p_dof_[I] >= 0) p_[I] = p0[I] + alpha * p_weight_[I] * delta[p_dof_[I]];
      follow_tail_nodes();
      restore_state(saved_);
      norm = evaluate(dt);
      if (halving == 6 || (std::isfinite(norm) && merit() <= (1 - 1e-4 * alpha) * before)) break;
      alpha /= 2;
    }
    residuals_.push_back(force_scale_ > 0 ? norm / force_scale_ : norm);
    last_step_is_round_off = alpha == 1 && round_off(delta);
  }
  describe_failure();
  restore_state(saved_);
  return false;
}

void QuasiStatic::reject_attempt() {
  restore_state(saved_);
  if (materials_.writes_eigenstrain() && !reduction_) restore_state(step_start_);
}

double QuasiStatic::largest_increment() const {
  const auto dim = static_cast<std::size_t>(d_.dim());
  double largest = 0;
  for (std::size_t I = 0; I < node_mass_.size(); ++I) {
    if (node_mass_[I] <= 0) continue;
    double sq = 0;
    for (std::size_t i = 0; i < dim; ++i) sq += du_[I * dim + i] * du_[I * dim + i];
    largest = std::max(largest, sq);
  }
  return d_.comm.max(std::sqrt(largest));
}

QuasiStatic::Held QuasiStatic::held_by(std::size_t b) const {
  const auto dim = static_cast<std::size_t>(d_.dim());
  Held held;
  std::array<double, 3> mass{}, moved{};
  for (const std::size_t k : held_[b]) {
    const std::size_t I = k / dim, i = k % dim;
    if (node_mass_[I] <= 0) continue;
    held.force[i] += f_int_[k] - f_ext_[k];
    // With inertia the constraint also accelerates its nodes' mass.
    if (!inertia_.empty()) held.force[i] += inertia_[k] * (du_[k] - inertia_target_[k]);
    mass[i] += node_mass_[I];
    moved[i] += node_mass_[I] * du_[k];
  }
  for (std::size_t i = 0; i < dim; ++i) {
    const double m = mass[i];  // every process holds every node's (sum_over_processes)
    if (m > 0) held.displacement[i] = moved[i] / m;
  }
  return held;
}

void QuasiStatic::describe_failure() {
  const int dim = d_.dim();
  std::size_t worst = 0;
  double largest = -1;
  for (std::size_t k = 0; k < u_dof_.size(); ++k)
    if (u_dof_[k] >= 0 && std::abs(residual_[static_cast<std::size_t>(u_dof_[k])]) > largest)
      largest = std::abs(residual_[static_cast<std::size_t>(u_dof_[k])]), worst = k;
  std::ostringstream out;
  out.precision(3);
  auto position = [&](const double* x) {
    out << "(";
    for (int a = 0; a < dim; ++a) out << (a ? ", " : "") << x[a];
    out << ") m";
  };
  if (largest >= 0 && std::isfinite(largest)) {
    const auto node = d_.grid.node_position(static_cast<std::int64_t>(worst / static_cast<std::size_t>(dim)));
    out << "the largest out-of-balance force, " << largest << (dim == 2 ? " N/m" : " N") << " ("
        << largest / force_scale_ << " of the forces; /time/newton_tolerance " << scene_.quasi_static.newton_tolerance
        << "), is at the node ";
    position(node.data());
  }
  // Points whose tangent is zero: at the apex of a yield surface, or separated.
  const double* x = d_.points.data(d_.points.core().position);
  std::vector<double> stiffless_count{0.0};
  std::array<double, 3> lo{}, hi{};
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (std::size_t p = 0; p < d_.points.size() && tangent_.size() >= (p + 1) * 36; ++p) {
    if (!without_stiffness(&tangent_[p * 36])) continue;
    for (int a = 0; a < dim; ++a) {
      lo[a] = std::min(lo[a], x[p * dim + a]);
      hi[a] = std::max(hi[a], x[p * dim + a]);
    }
    stiffless_count[0] += 1;
  }
  sum_over_processes(stiffless_count);
  for (int a = 0; a < dim; ++a) lo[a] = d_.comm.min(lo[a]), hi[a] = d_.comm.max(hi[a]);
  const auto stiffless = static_cast<std::size_t>(stiffless_count[0]);
  if (singular_) out << (largest >= 0 ? "; " : "") << "the system was singular (a mechanism without stiffness)";
  if (stiffless > 0) {
    out << "; " << stiffless << " material point" << (stiffless > 1 ? "s" : "")
        << " had no stiffness at the last iteration (a stress at the apex of the yield surface, or separated), between ";
    position(lo.data());
    out << " and ";
    position(hi.data());
  }
  failure_ = out.str();
}

}  // namespace suffuse::detail
