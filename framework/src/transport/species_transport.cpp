#include "transport/species_transport.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <ostream>

#include "parallel/distributed_system.hpp"
#include "mpm/plugin_batch.hpp"
#include "transport/species_kernels.hpp"
#include "mpm/initial_values.hpp"
#include "suffuse/error.hpp"
#include "suffuse/grid_face.hpp"

namespace suffuse::detail {

bool SpeciesTransport::tracks_fines(const Scene& scene, const std::vector<LiquidOpening>& openings) {
  bool fines = scene.erodible();
  for (const BodySpec& b : scene.bodies) {
    const auto& given = b.point_values.fines_content;
    fines = fines || b.fines_content > 0 || b.concentration > 0 ||
            std::any_of(given.begin(), given.end(), [](double f) { return f > 0; });
  }
  for (const LiquidOpening& o : openings) fines = fines || o.concentration > 0;
  return fines;
}

std::vector<FieldDeclaration<FinesFields>> SpeciesTransport::fines_fields_declared() {
  using K = FieldKind;
  using F = FinesFields;
  return {
      {{"skeleton_fines", K::Scalar, "kg", "erodible fines in the skeleton", false}, &F::skeleton_fines},
      {{"suspended_fines", K::Scalar, "kg", "fines carried by the pore liquid", false}, &F::suspended_fines},
      {{"eroded_mass", K::Scalar, "kg", "solid lost to the liquid, net", false}, &F::eroded_mass},
      {{coupling::fines_content, K::Scalar, "-", "f_c, erodible fines / solid volume", true}, &F::fines_content},
      {{coupling::fines_content_increment, K::Scalar, "-", "change of f_c over the step", false},
       &F::fines_content_increment},
      {{"ultimate_fines_content", K::Scalar, "-", "f_c_inf, fines no law can erode", false},
       &F::ultimate_fines_content},
      {{"concentration", K::Scalar, "-", "c, suspended fines / pore liquid volume", true}, &F::concentration},
      {{coupling::eroded_fraction, K::Scalar, "-", "f_er, eroded solid / initial solid mass", true},
       &F::eroded_fraction},
      {{coupling::eroded_fraction_increment, K::Scalar, "-", "change of f_er over the step", false},
       &F::eroded_fraction_increment},
      {{"erosion_rate", K::Scalar, "1/s", "n_e, eroded solid volume / volume / time", true}, &F::erosion_rate},
      {{"hydraulic_gradient", K::Scalar, "-", "|i| = |q| / K", true}, &F::hydraulic_gradient},
      {{"carrying_liquid", K::Scalar, "kg", "pore liquid carrying the suspension, its fines included", false},
       &F::carrying_liquid},
  };
}

namespace {
std::vector<LiquidOpening> openings_of(const std::vector<std::unique_ptr<BoundaryCondition>>& bcs) {
  std::vector<LiquidOpening> all;
  for (const auto& bc : bcs)
    for (const LiquidOpening& o : bc->liquid_openings()) all.push_back(o);
  return all;
}
}  // namespace

SpeciesTransport::~SpeciesTransport() = default;

SpeciesTransport::SpeciesTransport(const Scene& scene, const Registry& registry, Domain& domain,
                                   const SaturatedMixture& mixture,
                                   const std::vector<std::unique_ptr<BoundaryCondition>>& bcs)
    : d_(domain), m_(mixture.fields()), node_darcy_(mixture.nodal_darcy_flux()) {
  for (const MaterialSpec& m : scene.materials) {
    erosion_names_.push_back(m.erosion ? plugin_of_material("erosion law", *m.erosion, m.name) : std::string());
    erosion_.push_back(m.erosion ? registry.create<ErosionLaw>(m.erosion->type,
                                                              {m.erosion->params, scene.dim, m.erosion->pointer})
                                 : nullptr);
  }
  if (tracks_fines(scene, openings_of(bcs))) fines_ = register_fields(d_.points, fines_fields_declared());
  const std::size_t nn = d_.grid.node_count();
  node_face_.assign(nn * scene.dim, 0.0);
  for (auto* v : {&node_pore_, &node_liquid_, &node_fines_, &node_carrying_, &node_out_, &node_dliquid_,
                  &node_dfines_, &node_dcarrying_, &node_free_liquid_, &node_free_fines_, &node_free_carrying_,
                  &stage_dliquid_, &stage_dfines_, &stage_dcarrying_, &stage_liquid_, &stage_fines_, &stage_carrying_,
                  &node_per_pore_, &node_fines_ratio_, &node_carrying_ratio_, &node_send_})
    v->assign(nn, 0.0);
  face_flow_.assign(nn * scene.dim * 3, 0.0);
  share_block_.assign(nn * share_block, 0.0);  // the fines' rates stay zero where the run tracks none
  setup_openings(scene, mixture, bcs);
}

void SpeciesTransport::initialise(const BodySpec& body, const BodyPoints& b, const InitialValues& initial) {
  if (!body.liquid || !fines_) return;
  PointSet& pts = d_.points;
  const FinesFields& f = *fines_;
  const double* V = pts.data(pts.core().volume);
  const double* ms = pts.data(pts.core().mass);
  const double* n = pts.data(m_.porosity);
  const double* rho_s = pts.data(m_.grain_density);
  const double* ml = pts.data(m_.liquid_mass);
  const double* S = m_.saturation ? pts.data(*m_.saturation) : nullptr;  // pores that drain hold less
  for (std::size_t p = b.range.begin; p < b.range.end; ++p) {
    // A body's initial liquid carries fines (all of it) or none.
    pts.data(f.carrying_liquid)[p] = body.concentration > 0 ? ml[p] : 0.0;
    const double fc = initial.fines_content(p);
    pts.data(f.skeleton_fines)[p] = fc * ms[p];
    pts.data(f.suspended_fines)[p] = body.concentration * rho_s[p] * n[p] * V[p] * (m_.saturation ? S[p] : 1.0);
    pts.data(f.fines_content)[p] = fc;
    pts.data(f.ultimate_fines_content)[p] = body.ultimate_fines_content;
    pts.data(f.concentration)[p] = body.concentration;
  }
}

void SpeciesTransport::start_ledger() {
  const MassLedger start = mass_ledger(0);
  initial_solid_ = start.solid;
  initial_liquid_ = start.liquid;
  initial_fines_ = start.skeleton_fines + start.suspended_fines;
  erosion_scratch_.resize(static_cast<std::size_t>(d_.exec.threads()));
  for (ErosionScratch& s : erosion_scratch_)
    for (auto* v : {&s.flux_magnitude, &s.carrier_share, &s.carrier_concentration, &s.clean_concentration,
                    &s.clean_rate})
      v->assign(erosion_block, 0.0);
}

void SpeciesTransport::setup_openings(const Scene& scene, const SaturatedMixture& mixture,
                                      const std::vector<std::unique_ptr<BoundaryCondition>>& bcs) {
  // Densities of the liquid entering: the first saturated body's.
  double rho_s = 0, rho_w = 0;
  for (const BodySpec& b : scene.bodies)
    if (b.liquid && rho_w == 0) rho_s = mixture.grain_density(b.material), rho_w = mixture.liquid(*b.liquid).density();
  clean_water_density_ = rho_w;
  const int dim = d_.dim();
  inflow_liquid_.assign(d_.grid.node_count() * dim, std::numeric_limits<double>::quiet_NaN());
  inflow_fines_ = inflow_liquid_;
  inflow_carrying_ = inflow_liquid_;
  std::vector<std::string> opened_by;  // the JSON pointer of each opening's condition
  for (std::size_t b = 0; b < bcs.size(); ++b) {
    for (const LiquidOpening& o : bcs[b]->liquid_openings()) {
      const std::string& pointer = scene.boundary_conditions[b].pointer;
      const std::string face_name = grid_face_names()[o.face.axis * 2 + (o.face.upper ? 1 : 0)];
      const std::string name = o.name.empty() ? face_name : o.name;
      const std::vector<std::int64_t> nodes = o.nodes.empty() ? face_nodes(d_.grid, o.face) : o.nodes;
      const auto faces = grid_face_names();
      const bool plain = !name.empty() && std::all_of(name.begin(), name.end(), [](unsigned char c) {
        return std::isalnum(c) || c == '_';
      });
      if (!plain || name == "free_surface" || (name != face_name && std::find(faces.begin(), faces.end(), name) != faces.end()))
        throw Error(pointer + "/name: not a name for a ledger account; expected letters, digits and '_', other "
                    "than \"free_surface\" and another face's name, found \"" + name + "\"");
      for (std::size_t k = 0; k < openings_.size(); ++k) {
        const std::vector<std::int64_t>& other = openings_[k].ids;
        // Both lists ascend (face_nodes): one merge finds a shared node.
        bool shared = false;
        if (openings_[k].face.axis == o.face.axis && openings_[k].face.upper == o.face.upper)
          for (std::size_t i = 0, j = 0; !shared && i < nodes.size() && j < other.size();) {
            if (nodes[i] < other[j]) ++i;
            else if (other[j] < nodes[i]) ++j;
            else shared = true;
          }
        if (shared)
          throw Error(pointer + " and " + opened_by[k] + " both open " +
                      (o.nodes.empty() ? "the " + face_name + " face" : "nodes of the " + face_name + " face") +
                      " of the grid to the liquid; its outflow would be counted twice: keep one bc/pore_pressure "
                      "or bc/inflow_flux per face, or give each a part of it apart (box_min, box_max)");
        if (discharge_[k].face == name)
          throw Error(pointer + " and " + opened_by[k] + " both book what crosses them as '" + name +
                      "' in the mass ledger; expected a \"name\" for each part of a face, found the same name");
      }
      opened_by.push_back(pointer);
      Opening opening{o.face, {}, {}, {}};
      for (std::int64_t I : nodes) {
        opening.nodes.push_back({I, d_.periodic.face_area(d_.grid, o.face, I)});
        opening.ids.push_back(I);
        const std::size_t k = static_cast<std::size_t>(I) * dim + o.face.axis;
        inflow_liquid_[k] = suspension_density(o.concentration, rho_s, rho_w);
        inflow_fines_[k] = o.concentration * rho_s;
        inflow_carrying_[k] = o.concentration > 0 ? inflow_liquid_[k] : 0.0;  // carries fines, or clean
      }
      discharge_.push_back({name, 0, 0, 0, 0, face_name});
      opening.crossed.resize(opening.nodes.size());
      openings_.push_back(std::move(opening));
    }
  }
  // Liquid leaving the body through a free surface inside the grid.
  discharge_.push_back({"free_surface", 0, 0, 0, 0, ""});
  discharge_step_.assign(discharge_.size(), {0, 0, 0, 0});
  discharge_carry_.assign(discharge_.size(), {0, 0, 0, 0});
}

bool SpeciesTransport::erode(double dt) {
  if (!fines_) return false;
  const FinesFields& f = *fines_;
  PointSet& pts = d_.points;
  const int dim = d_.dim();
  const double* flux = step_mean_flux_.empty() ? pts.data(m_.darcy_flux) : step_mean_flux_.data();
  const SpeciesPoints pt{pts.data(pts.core().mass),     pts.data(f.skeleton_fines), pts.data(f.suspended_fines),
                         pts.data(m_.liquid_mass),      pts.data(f.eroded_mass),    pts.data(pts.core().volume),
                         pts.data(m_.porosity),         pts.data(m_.grain_density), pts.data(f.carrying_liquid)};
  std::vector<char>& moved = eroded_in_chunk_;
  moved.assign(static_cast<std::size_t>(d_.exec.threads()), 0);
  for (const BodyPoints& body : d_.bodies) {
    const ErosionLaw* law = erosion_[body.material].get();
    if (!body.saturated || !law) continue;
    d_.exec.for_chunks(body.range.size(), [&](int chunk, std::size_t b, std::size_t e) {
      ErosionScratch& scratch = erosion_scratch_[static_cast<std::size_t>(chunk)];
      for (std::size_t first = body.range.begin + b; first < body.range.begin + e; first += erosion_block) {
        const std::size_t begin = first, end = std::min(body.range.begin + e, first + erosion_block),
                          count = end - begin;
        const ErosionInputs in{flux,                             pts.data(m_.conductivity),
                               pts.data(m_.water_density),       scratch.flux_magnitude.data(),
                               pts.data(f.hydraulic_gradient),   pts.data(f.fines_content),
                               pts.data(f.concentration),        scratch.carrier_share.data(),
                               scratch.carrier_concentration.data()};
        bool mixed = false;  // some points hold clean water beside the suspension
        d_.exec.vector_kernel(dim, [&]<int D, int L>() { mixed = erosion_inputs<D, L>(begin, end, pt, in); });
        auto span = [&](FieldId id) { return std::span<const double>(pts.data(id) + begin, count); };
        auto block = [&](const std::vector<double>& v) { return std::span<const double>(v.data(), count); };
        double* rate = pts.data(f.erosion_rate);
        // The law sees the liquid that carries the fines, at its own c: a
        // point where the transport has mixed suspension and clean water at a
        // front erodes as its two parts would, share x rate(c_carrying) +
        // (1 - share) x rate(0), not at the mixture's c (docs/erosion.md,
        // Mesh convergence).
        const PointRange batch{begin, end};
        run_plugin_on_batch(d_, body, batch, erosion_names_[body.material], [&] {
          law->rate(ErosionBatch{span(m_.porosity), span(f.fines_content), span(f.ultimate_fines_content),
                                 block(scratch.carrier_concentration), block(scratch.flux_magnitude),
                                 span(f.hydraulic_gradient), std::span<double>(rate + begin, count)});
        });
        const double* share = scratch.carrier_share.data();
        const double* clean_rate = scratch.clean_rate.data();
        if (mixed) {
          run_plugin_on_batch(d_, body, batch, erosion_names_[body.material], [&] {
            law->rate(ErosionBatch{span(m_.porosity), span(f.fines_content), span(f.ultimate_fines_content),
                                   block(scratch.clean_concentration), block(scratch.flux_magnitude),
                                   span(f.hydraulic_gradient),
                                   std::span<double>(scratch.clean_rate.data(), count)});
          });
          for (std::size_t p = begin; p < end; ++p)
            if (share[p - begin] < 1)
              rate[p] = share[p - begin] * rate[p] + (1 - share[p - begin]) * clean_rate[p - begin];
        }
        const ErosionState st{pts.data(f.fines_content), pts.data(f.eroded_fraction),
                              pts.data(m_.porosity_increment), pts.data(f.fines_content_increment),
                              pts.data(f.eroded_fraction_increment)};
        const double* ultimate = pts.data(f.ultimate_fines_content);
        d_.exec.vector_kernel(dim, [&]<int, int L>() {
          moved[chunk] = erode_points<L>(begin, end, dt, pt, ultimate, rate, st) || moved[chunk];
        });
        // Clean water that took up fines (a law that erodes at c = 0) carries them now.
        if (mixed)
          for (std::size_t p = begin; p < end; ++p)
            if (share[p - begin] < 1 && clean_rate[p - begin] > 0 && rate[p] > 0)
              pt.carrying_liquid[p] = pt.liquid_mass[p];
      }
    });
  }
  return std::find(moved.begin(), moved.end(), 1) != moved.end();
}

void SpeciesTransport::explicit_stage(double dt, const double* liquid, const double* fines_at,
                                      const double* carrying_at, std::vector<std::array<double, 4>>& step) {
  const bool fines = fines_.has_value();
  const int dim = d_.dim();
  const TransportGrid g{d_.grid.nodes_per_axis(), d_.grid.cell_size(), dt, node_pore_.data(), liquid,
                        fines ? fines_at : nullptr, fines ? carrying_at : nullptr, node_darcy_.data(),
                        node_face_.data(), inflow_liquid_.data(), inflow_fines_.data(), inflow_carrying_.data(),
                        water_ ? node_submerged_.data() : nullptr, clean_water_density_};
  auto run = [&](auto transport) {
    d_.for_nodes([&](int, std::size_t b, std::size_t e) { transport.faces(b, e); });
    d_.for_nodes([&](int, std::size_t b, std::size_t e) { transport.outflow(b, e, node_out_.data()); });
    // Open faces: liquid leaving also counts against a node's content (a
    // quarter: it leaves at the node's mean, see Transport::scale).
    for (const Opening& o : openings_)
      for (const OpeningNode& on : o.nodes)
        node_out_[on.node] +=
            0.25 * std::max(0.0, dt * on.area * o.face.outward() * transport.darcy(on.node, o.face.axis));
    const NodeShares shares{node_per_pore_.data(), node_fines_ratio_.data(), node_carrying_ratio_.data(),
                            node_send_.data(), face_flow_.data()};
    d_.for_nodes([&](int, std::size_t b, std::size_t e) { transport.shares(b, e, node_out_.data(), shares); });
    d_.for_nodes([&](int, std::size_t b, std::size_t e) { transport.flows(b, e, shares); });
    d_.for_nodes([&](int, std::size_t b, std::size_t e) {
      transport.exchange(b, e, shares, node_dliquid_.data(), node_dfines_.data(), node_dcarrying_.data(),
                         node_free_liquid_.data(), node_free_fines_.data(), node_free_carrying_.data(),
                         node_free_water_in_.data());
    });
    // What crossed each account this step, summed in node order (independent
    // of the chunking and of the processes): out, in of liquid; out, in of fines.
    const Domain::NodeTerms free = d_.node_sums(water_ ? 3 : 2, [&](std::size_t I, double* t) {
      t[0] = node_free_liquid_[I];
      t[1] = node_free_fines_[I];
      if (water_) t[2] = node_free_water_in_[I];
      return t[0] != 0 || t[1] != 0 || (water_ && t[2] != 0);
    });
    step.back() = {free[0], water_ ? free[2] : 0.0, free[1], 0};
    for (std::size_t k = 0; k < openings_.size(); ++k) {
      Opening& o = openings_[k];  // the free surfaces' account is the last
      for (std::size_t i = 0; i < o.nodes.size(); ++i) {
        const std::int64_t I = o.nodes[i].node;
        std::array<double, 4>& crossed = o.crossed[i];
        crossed = {0, 0, 0, 0};
        if (node_pore_[I] <= 0) continue;
        const double vol = dt * o.nodes[i].area * o.face.outward() * transport.darcy(I, o.face.axis);
        if (vol > 0) {
          discharge(static_cast<std::size_t>(I), transport.scale(I, node_out_.data()) * vol / node_pore_[I], liquid,
                    fines_at, carrying_at, crossed);
        } else if (vol < 0) {
          // What enters per volume, set once per face node in setup_openings.
          const std::size_t at = static_cast<std::size_t>(I) * dim + o.face.axis;
          const double liquid_in = -vol * inflow_liquid_[at], fines_in = -vol * inflow_fines_[at];
          node_dliquid_[I] += liquid_in;
          node_dfines_[I] += fines_in;
          node_dcarrying_[I] += -vol * inflow_carrying_[at];
          crossed[1] = liquid_in;
          crossed[3] = fines_in;
        }
      }
      const Domain::NodeTerms sums = d_.node_sums(4, o.ids, [&](std::size_t i, double* t) {
        std::copy(o.crossed[i].begin(), o.crossed[i].end(), t);
        return true;
      });
      step[k] = {sums[0], sums[1], sums[2], sums[3]};
    }
  };
  if (dim == 2)
    run(Transport<2>{g});
  else
    run(Transport<3>{g});
}

void SpeciesTransport::discharge(std::size_t I, double share, const double* liquid, const double* fines,
                                 const double* carrying, std::array<double, 4>& account) {
  const double liquid_out = share * liquid[I], fines_out = fines_ ? share * fines[I] : 0.0;
  node_dliquid_[I] -= liquid_out;
  node_dfines_[I] -= fines_out;
  if (fines_) node_dcarrying_[I] -= share * carrying[I];
  account[0] += liquid_out;
  account[2] += fines_out;
}

void SpeciesTransport::set_standing_water(const StandingWaterLoad* water) {
  water_ = water;
  node_submerged_.assign(d_.grid.node_count(), 0);
  node_free_water_in_.assign(d_.grid.node_count(), 0.0);
}

const double* SpeciesTransport::water_filled_porosity() {
  const PointSet& pts = d_.points;
  if (!m_.saturation) return pts.data(m_.porosity);
  const double* n = pts.data(m_.porosity);
  const double* S = pts.data(*m_.saturation);
  water_filled_.resize(pts.size());
  d_.exec.for_chunks(pts.size(), [&](int, std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) water_filled_[p] = n[p] * S[p];
  });
  return water_filled_.data();
}

void SpeciesTransport::transport(double dt, TransportScheme scheme) {
  if (water_) {  // the nodes still water stands above, this step
    const WaterProfile& water = water_->current();
    const int dim = d_.dim();
    d_.for_nodes([&](int, std::size_t b, std::size_t e) {
      for (std::size_t I = b; I < e; ++I) {
        const auto x = d_.grid.node_position(static_cast<std::int64_t>(I));
        node_submerged_[I] = x[dim - 1] < water.level(x[0]).first;
      }
    });
  }
  PointSet& pts = d_.points;
  const double* V = pts.data(pts.core().volume);
  const double* n = water_filled_porosity();
  const Interpolation& s = d_.shape;
  d_.clear_nodal(species_block_, species_block);
  ScatterTargets targets = s.targets(d_.grid.node_count());
  targets.add(species_block_);
  // Whether the run tracks fines is fines_, never these pointers: a process
  // that holds no point has null field pointers (docs/parallel.md).
  const double* fines = fines_ ? pts.data(fines_->suspended_fines) : nullptr;
  const double* carrying = fines_ ? pts.data(fines_->carrying_liquid) : nullptr;
  d_.exec.scatter(pts.size(), targets, [&](std::size_t b, std::size_t e, double* const* out) {
    d_.exec.vector_kernel(d_.dim(), [&]<int D, int L>() {
      p2g_species<D, L>(b, e, s.view(), V, n, pts.data(m_.liquid_mass), fines, carrying,
                     out[0]);
    });
  });
  d_.for_nodes([&](int, std::size_t b, std::size_t e) {
    unpack_species_block(b, e, species_block_.data(), node_pore_.data(), node_liquid_.data(),
                         fines_ ? node_fines_.data() : nullptr, fines_ ? node_carrying_.data() : nullptr);
  });

  if (scheme == TransportScheme::backward_euler) {
    implicit_stage(dt);
  } else {
    explicit_stage(dt, node_liquid_.data(), node_fines_.data(), node_carrying_.data(), discharge_step_);
  }
  if (scheme == TransportScheme::heun) {
    // Heun: U1 = U + D(U); the step's change is (D(U) + D(U1)) / 2, and so is
    // what crossed each account.
    d_.for_nodes([&](int, std::size_t b, std::size_t e) {
      for (std::size_t I = b; I < e; ++I) {
        stage_dliquid_[I] = node_dliquid_[I], stage_liquid_[I] = node_liquid_[I] + node_dliquid_[I];
        stage_dfines_[I] = node_dfines_[I], stage_fines_[I] = node_fines_[I] + node_dfines_[I];
        stage_dcarrying_[I] = node_dcarrying_[I], stage_carrying_[I] = node_carrying_[I] + node_dcarrying_[I];
      }
    });
    stage_discharge_ = discharge_step_;
    explicit_stage(dt, stage_liquid_.data(), stage_fines_.data(), stage_carrying_.data(), discharge_step_);
    d_.for_nodes([&](int, std::size_t b, std::size_t e) {
      for (std::size_t I = b; I < e; ++I) {
        node_dliquid_[I] = 0.5 * (stage_dliquid_[I] + node_dliquid_[I]);
        node_dfines_[I] = 0.5 * (stage_dfines_[I] + node_dfines_[I]);
        node_dcarrying_[I] = 0.5 * (stage_dcarrying_[I] + node_dcarrying_[I]);
      }
    });
    for (std::size_t k = 0; k < discharge_step_.size(); ++k)
      for (int i = 0; i < 4; ++i) discharge_step_[k][i] = 0.5 * (stage_discharge_[k][i] + discharge_step_[k][i]);
  }
  add_to_totals(discharge_step_);

  const PoreLiquidPoints liquid{V,
                                n,
                                pts.data(m_.grain_density),
                                pts.data(m_.water_density),
                                fines,
                                pts.data(m_.liquid_mass),
                                fines_ ? pts.data(fines_->concentration) : nullptr,
                                pts.data(m_.liquid_density),
                                pts.data(m_.moving_liquid_mass)};
  d_.for_nodes([&](int, std::size_t b, std::size_t e) {
    share_rates(b, e, 0, node_pore_.data(), node_liquid_.data(), node_dliquid_.data(), share_block_.data());
    if (fines_) {
      share_rates(b, e, 1, node_pore_.data(), node_fines_.data(), node_dfines_.data(), share_block_.data());
      share_rates(b, e, 2, node_pore_.data(), node_carrying_.data(), node_dcarrying_.data(), share_block_.data());
    }
  });
  double* const amounts[3] = {pts.data(m_.liquid_mass), fines ? pts.data(fines_->suspended_fines) : nullptr,
                              fines ? pts.data(fines_->carrying_liquid) : nullptr};
  d_.exec.for_chunks(pts.size(), [&](int, std::size_t b, std::size_t e) {
    d_.exec.vector_kernel(d_.dim(), [&]<int D, int L>() {
      g2p_share<D, L>(b, e, s.view(), V, n, share_block_.data(), amounts);
      pore_liquid_density<L>(b, e, liquid);
    });
  });
}

double SpeciesTransport::composition_change() const {
  if (!fines_) return 0;
  double fines = 0, carrying = 0, largest_fines = 0;
  for (const ScatterRange& r : d_.owned_nodes(d_.shape)) {  // each node once, on its owner
    for (std::size_t I = r.first; I < r.last; ++I) {
      const double L0 = node_liquid_[I], L1 = L0 + node_dliquid_[I];
      if (!(node_pore_[I] > 0 && L0 > 0 && L1 > 0)) continue;
      const double f0 = node_fines_[I] / L0, f1 = (node_fines_[I] + node_dfines_[I]) / L1;
      fines = std::max(fines, std::abs(f1 - f0));
      largest_fines = std::max({largest_fines, f0, f1});
      carrying = std::max(carrying, std::abs((node_carrying_[I] + node_dcarrying_[I]) / L1 - node_carrying_[I] / L0));
    }
  }
  fines = d_.comm.max(fines), carrying = d_.comm.max(carrying), largest_fines = d_.comm.max(largest_fines);
  return std::max(largest_fines > 0 ? fines / largest_fines : 0.0, carrying);
}

void SpeciesTransport::start_step() {
  if (!fines_) return;
  const PointSet& pts = d_.points;
  const auto fc = pts.values(fines_->fines_content), fer = pts.values(fines_->eroded_fraction);
  step_fines_content_.assign(fc.begin(), fc.end());
  step_eroded_fraction_.assign(fer.begin(), fer.end());
  if (step_mean_flux_.empty()) return;  // no flux kept at the step's start
  const auto end = pts.values(m_.darcy_flux);
  for (std::size_t k = 0; k < end.size(); ++k) step_mean_flux_[k] = 0.5 * (step_mean_flux_[k] + end[k]);
}

void SpeciesTransport::keep_flux_at_start() {
  if (!fines_) return;
  const auto q = d_.points.values(m_.darcy_flux);
  step_mean_flux_.assign(q.begin(), q.end());
}

void SpeciesTransport::finish_step() {
  step_mean_flux_.clear();
  if (!fines_) return;
  PointSet& pts = d_.points;
  const double* fc = pts.data(fines_->fines_content);
  const double* fer = pts.data(fines_->eroded_fraction);
  double* dfc = pts.data(fines_->fines_content_increment);
  double* dfer = pts.data(fines_->eroded_fraction_increment);
  d_.exec.for_chunks(pts.size(), [&](int, std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) {
      dfc[p] = fc[p] - step_fines_content_[p];
      dfer[p] = fer[p] - step_eroded_fraction_[p];
    }
  });
}

double SpeciesTransport::largest_eroded_fraction_increment() const {
  if (!fines_) return 0;
  double worst = 0;
  for (const double d : d_.points.values(fines_->eroded_fraction_increment)) worst = std::max(worst, std::abs(d));
  return d_.comm.max(worst);
}

void SpeciesTransport::add_to_totals(const std::vector<std::array<double, 4>>& step) {
  // The totals grow large and a step's share stays small: Kahan summation
  // carries the low-order bits a plain addition drops.
  for (std::size_t k = 0; k < discharge_.size(); ++k) {
    BoundaryDischarge& d = discharge_[k];
    double* totals[4] = {&d.liquid_out, &d.liquid_in, &d.fines_out, &d.fines_in};
    for (int i = 0; i < 4; ++i) {
      double& carry = discharge_carry_[k][i];
      const double y = step[k][i] - carry, t = *totals[i] + y;
      carry = (t - *totals[i]) - y;
      *totals[i] = t;
    }
  }
}

std::vector<double> SpeciesTransport::saved_state() const {
  std::vector<double> state{initial_solid_, initial_liquid_, initial_fines_};
  for (std::size_t k = 0; k < discharge_.size(); ++k) {
    const BoundaryDischarge& d = discharge_[k];
    state.insert(state.end(), {d.liquid_out, d.liquid_in, d.fines_out, d.fines_in});
    state.insert(state.end(), discharge_carry_[k].begin(), discharge_carry_[k].end());
  }
  return state;
}

void SpeciesTransport::restore_state(const std::vector<double>& state) {
  if (state.size() != 3 + 8 * discharge_.size())
    throw Error("checkpoint: the ledger saved " + std::to_string(state.size() < 3 ? 0 : (state.size() - 3) / 8) +
                " boundaries, the scene has " + std::to_string(discharge_.size()));
  initial_solid_ = state[0];
  initial_liquid_ = state[1];
  initial_fines_ = state[2];
  for (std::size_t k = 0; k < discharge_.size(); ++k) {
    const double* v = state.data() + 3 + 8 * k;
    BoundaryDischarge& d = discharge_[k];
    d.liquid_out = v[0];
    d.liquid_in = v[1];
    d.fines_out = v[2];
    d.fines_in = v[3];
    std::copy(v + 4, v + 8, discharge_carry_[k].begin());
  }
}

}  // namespace suffuse::detail
