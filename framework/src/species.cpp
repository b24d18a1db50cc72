// Species balances of saturated runs: erosion of the skeleton's fines, the
// transport of the pore liquid and its suspended fines across the grid, and
// the mass ledger. Formulation and verification: docs/erosion.md.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <ostream>

#include "simulation_parallel.hpp"
#include "species_kernels.hpp"
#include "suffuse/grid_face.hpp"
#include "suffuse/error.hpp"
#include "suffuse/simulation.hpp"

namespace suffuse {

namespace {

using Clock = std::chrono::steady_clock;

struct Timer {
  double& total;
  Clock::time_point start = Clock::now();
  ~Timer() { total += std::chrono::duration<double>(Clock::now() - start).count(); }
};

double relative(double in, double residual) { return in > 0 ? std::abs(residual) / in : std::abs(residual); }

}  // namespace

double MassLedger::fines_discharged() const {
  double out = 0;
  for (const auto& b : boundaries) out += b.fines_out;
  return out;
}

double MassLedger::solid_imbalance() const { return relative(initial_solid, initial_solid - solid - eroded); }

double MassLedger::liquid_imbalance() const {
  double in = initial_liquid + eroded, out = 0;
  for (const auto& b : boundaries) in += b.liquid_in, out += b.liquid_out;
  return relative(in, in - liquid - out);
}

double MassLedger::fines_imbalance() const {
  double in = initial_fines, out = 0;
  for (const auto& b : boundaries) in += b.fines_in, out += b.fines_out;
  return relative(in, in - skeleton_fines - suspended_fines - out);
}

void Simulation::add_species_fields() {
  using K = FieldKind;
  ef_.grain_density = points_.add_field({"grain_density", K::Scalar, "kg/m^3", "density rho_s of the solid", false});
  ef_.water_density =
      points_.add_field({"water_density", K::Scalar, "kg/m^3", "density rho_w of the clean pore liquid", false});
  if (!fines_) return;
  ef_.skeleton_fines = points_.add_field({"skeleton_fines", K::Scalar, "kg", "erodible fines in the skeleton", false});
  ef_.suspended_fines =
      points_.add_field({"suspended_fines", K::Scalar, "kg", "fines carried by the pore liquid", false});
  ef_.eroded_mass = points_.add_field({"eroded_mass", K::Scalar, "kg", "solid lost to the liquid, net", false});
  ef_.fines_content =
      points_.add_field({"fines_content", K::Scalar, "-", "f_c, erodible fines / solid volume", true});
  ef_.ultimate_fines_content = points_.add_field(
      {"ultimate_fines_content", K::Scalar, "-", "f_c_inf, fines no law can erode", false});
  ef_.concentration =
      points_.add_field({"concentration", K::Scalar, "-", "c, suspended fines / pore liquid volume", true});
  ef_.eroded_fraction =
      points_.add_field({"eroded_fraction", K::Scalar, "-", "f_er, eroded solid / initial solid mass", true});
  ef_.erosion_rate =
      points_.add_field({"erosion_rate", K::Scalar, "1/s", "n_e, eroded solid volume / volume / time", true});
  ef_.hydraulic_gradient =
      points_.add_field({"hydraulic_gradient", K::Scalar, "-", "|i| = |q| / K", true});
}

void Simulation::set_species_state(const BodySpec& body, PointRange range) {
  const double rho_s = phases_[body.material]->density();
  const double rho_w = liquids_[*body.liquid]->density();
  const double* V = points_.data(points_.core().volume);
  const double* ms = points_.data(points_.core().mass);
  double* n = points_.data(sf_.porosity);
  for (std::size_t p = range.begin; p < range.end; ++p) {
    const double pore = n[p] * V[p], c = body.concentration;
    points_.data(ef_.grain_density)[p] = rho_s;
    points_.data(ef_.water_density)[p] = rho_w;
    points_.data(sf_.liquid_mass)[p] = pore * (c * rho_s + (1 - c) * rho_w);
    points_.data(sf_.liquid_density)[p] = c * rho_s + (1 - c) * rho_w;
    points_.data(sf_.moving_liquid_mass)[p] = pore * (c * rho_s + (1 - c) * rho_w);
    if (!fines_) continue;
    points_.data(ef_.skeleton_fines)[p] = body.fines_content * ms[p];
    points_.data(ef_.suspended_fines)[p] = c * rho_s * pore;
    points_.data(ef_.fines_content)[p] = body.fines_content;
    points_.data(ef_.ultimate_fines_content)[p] = body.ultimate_fines_content;
    points_.data(ef_.concentration)[p] = c;
  }
}

void Simulation::setup_openings() {
  // Densities of the liquid entering: the first saturated body's.
  double rho_s = 0, rho_w = 0;
  for (const BodySpec& b : scene_.bodies)
    if (b.liquid && rho_w == 0) rho_s = phases_[b.material]->density(), rho_w = liquids_[*b.liquid]->density();
  const int dim = scene_.dim;
  inflow_liquid_.assign(grid_.node_count() * dim, std::numeric_limits<double>::quiet_NaN());
  inflow_fines_ = inflow_liquid_;
  for (const auto& bc : bcs_) {
    for (const LiquidOpening& o : bc->liquid_openings()) {
      for (const Opening& other : openings_)
        if (other.face.axis == o.face.axis && other.face.upper == o.face.upper)
          throw Error("two boundary conditions open the same grid face to the liquid; its outflow would be counted "
                      "twice: keep one bc/pore_pressure or bc/inflow_flux per face");
      Opening opening{o.face, {}};
      for (std::int64_t I : face_nodes(grid_, o.face)) {
        const auto ijk = grid_.node_ijk(I);
        double area = 1;
        for (int a = 0; a < dim; ++a) {
          if (a == o.face.axis) continue;
          const bool edge = ijk[a] == 0 || ijk[a] == grid_.nodes_per_axis()[a] - 1;
          area *= grid_.cell_size()[a] * (edge ? 0.5 : 1.0);
        }
        opening.nodes.push_back({I, area});
      }
      for (const OpeningNode& on : opening.nodes) {
        const std::size_t k = static_cast<std::size_t>(on.node) * dim + o.face.axis;
        inflow_liquid_[k] = o.concentration * rho_s + (1 - o.concentration) * rho_w;
        inflow_fines_[k] = o.concentration * rho_s;
      }
      static const char* names[3][2] = {{"left", "right"}, {"bottom", "top"}, {"front", "back"}};
      discharge_.push_back({names[o.face.axis][o.face.upper ? 1 : 0], 0, 0, 0, 0});
      openings_.push_back(std::move(opening));
    }
  }
  // Liquid leaving the body through a free surface inside the grid.
  discharge_.push_back({"free_surface", 0, 0, 0, 0});
  discharge_step_.assign(discharge_.size(), {0, 0, 0, 0});
  discharge_carry_.assign(discharge_.size(), {0, 0, 0, 0});
}

void Simulation::erode() {
  Timer t{times_.erosion};
  if (!fines_) return;
  const auto& f = points_.core();
  const int dim = scene_.dim;
  const detail::SpeciesPoints pt{points_.data(f.mass),          points_.data(ef_.skeleton_fines),
                                 points_.data(ef_.suspended_fines), points_.data(sf_.liquid_mass),
                                 points_.data(ef_.eroded_mass), points_.data(f.volume),
                                 points_.data(sf_.porosity),    points_.data(ef_.grain_density)};
  for (const MaterialRange& r : ranges_) {
    const ErosionLaw* law = erosion_[r.material].get();
    if (!r.saturated || !law) continue;
    for_chunks(r.range.size(), [&](int, std::size_t b, std::size_t e) {
      const std::size_t begin = r.range.begin + b, end = r.range.begin + e, count = e - b;
      const double* q = points_.data(sf_.darcy_flux);
      const double* K = points_.data(sf_.conductivity);
      double* fc = points_.data(ef_.fines_content);
      double* c = points_.data(ef_.concentration);
      double* grad = points_.data(ef_.hydraulic_gradient);
      const double* rho_w = points_.data(ef_.water_density);
      for (std::size_t p = begin; p < end; ++p) {
        double q2 = 0;
        for (int i = 0; i < dim; ++i) q2 += q[p * dim + i] * q[p * dim + i];
        flux_magnitude_[p] = std::sqrt(q2);
        grad[p] = flux_magnitude_[p] / K[p];  // Darcy: q = K i
        fc[p] = pt.skeleton_fines[p] / pt.solid_mass[p];
        c[p] = detail::suspended_concentration(pt.suspended_fines[p], pt.liquid_mass[p], pt.grain_density[p], rho_w[p]);
      }
      auto span = [&](FieldId id) { return std::span<const double>(points_.data(id) + begin, count); };
      double* rate = points_.data(ef_.erosion_rate);
      law->rate(ErosionBatch{span(sf_.porosity), span(ef_.fines_content), span(ef_.ultimate_fines_content),
                             span(ef_.concentration), std::span<const double>(flux_magnitude_.data() + begin, count),
                             span(ef_.hydraulic_gradient), std::span<double>(rate + begin, count)});
      for (std::size_t p = begin; p < end; ++p)
        if (!std::isfinite(rate[p]))
          throw Error("erosion law of material '" + scene_.materials[r.material].name + "' returned rate " +
                      std::to_string(rate[p]) + " at material point " + std::to_string(p) + " (n = " +
                      std::to_string(pt.porosity[p]) + ", f_c = " + std::to_string(fc[p]) + ", c = " +
                      std::to_string(c[p]) + ", |q| = " + std::to_string(flux_magnitude_[p]) + ")");
      detail::apply_erosion(begin, end, dt_, pt, points_.data(ef_.ultimate_fines_content), rate);
      double* fer = points_.data(ef_.eroded_fraction);
      for (std::size_t p = begin; p < end; ++p) {
        fc[p] = pt.skeleton_fines[p] / pt.solid_mass[p];
        fer[p] = pt.eroded_mass[p] / (pt.solid_mass[p] + pt.eroded_mass[p]);
      }
    });
  }
}

void Simulation::update_permeability() {
  for (const MaterialRange& r : ranges_)
    if (r.saturated) update_conductivity(r);
}

void Simulation::transport_liquid() {
  Timer t{times_.transport};
  const auto& f = points_.core();
  const double* V = points_.data(f.volume);
  const double* n = points_.data(sf_.porosity);
  for (auto* v : {&node_pore_, &node_liquid_, &node_fines_}) std::fill(v->begin(), v->end(), 0.0);
  ScatterTargets targets;
  targets.add(node_pore_);
  targets.add(node_liquid_);
  if (fines_) targets.add(node_fines_);
  const double* fines = fines_ ? points_.data(ef_.suspended_fines) : nullptr;
  scatter(targets, [&](std::size_t b, std::size_t e, double* const* out) {
    detail::p2g_species(b, e, npp_, node_ids_.data(), weights_.data(), V, n, points_.data(sf_.liquid_mass), fines,
                        out[0], out[1], fines_ ? out[2] : nullptr);
  });

  const detail::TransportGrid g{grid_.nodes_per_axis(),
                                grid_.cell_size(),
                                dt_,
                                node_pore_.data(),
                                node_liquid_.data(),
                                fines_ ? node_fines_.data() : nullptr,
                                node_darcy_.data(),
                                node_face_.data(),
                                inflow_liquid_.data(),
                                inflow_fines_.data()};
  const std::size_t nn = grid_.node_count();
  auto run = [&](auto transport) {
    for_chunks(nn, [&](int, std::size_t b, std::size_t e) { transport.faces(b, e); });
    for_chunks(nn, [&](int, std::size_t b, std::size_t e) { transport.outflow(b, e, node_out_.data()); });
    // Open faces: liquid leaving also counts against a node's content.
    for (const Opening& o : openings_)
      for (const OpeningNode& on : o.nodes)
        node_out_[on.node] +=
            std::max(0.0, dt_ * on.area * o.face.outward() * transport.darcy(on.node, o.face.axis));
    for_chunks(nn, [&](int, std::size_t b, std::size_t e) {
      transport.exchange(b, e, node_out_.data(), node_dliquid_.data(), node_dfines_.data(), node_free_liquid_.data(),
                         node_free_fines_.data());
    });
    // What crossed each account this step, summed in node order (independent
    // of the chunking), then added to the run's totals with compensated
    // summation: the totals grow large and the step's share stays small.
    std::vector<std::array<double, 4>>& step = discharge_step_;  // out, in of liquid; out, in of fines
    for (auto& a : step) a = {0, 0, 0, 0};
    for (std::size_t I = 0; I < nn; ++I) {
      step.back()[0] += node_free_liquid_[I];
      step.back()[2] += node_free_fines_[I];
    }
    for (std::size_t k = 0; k < openings_.size(); ++k) {
      const Opening& o = openings_[k];  // the free surfaces' account is the last
      for (const OpeningNode& on : o.nodes) {
        const std::int64_t I = on.node;
        if (node_pore_[I] <= 0) continue;
        const double vol = dt_ * on.area * o.face.outward() * transport.darcy(I, o.face.axis);
        if (vol > 0) {
          const double share = transport.scale(I, node_out_.data()) * vol / node_pore_[I];
          const double liquid = share * node_liquid_[I], fines_out = fines_ ? share * node_fines_[I] : 0.0;
          node_dliquid_[I] -= liquid;
          node_dfines_[I] -= fines_out;
          step[k][0] += liquid;
          step[k][2] += fines_out;
        } else if (vol < 0) {
          // What enters per volume, set once per face node in setup_openings.
          const std::size_t at = static_cast<std::size_t>(I) * scene_.dim + o.face.axis;
          const double liquid = -vol * inflow_liquid_[at], fines_in = -vol * inflow_fines_[at];
          node_dliquid_[I] += liquid;
          node_dfines_[I] += fines_in;
          step[k][1] += liquid;
          step[k][3] += fines_in;
        }
      }
    }
    for (std::size_t k = 0; k < discharge_.size(); ++k) {
      BoundaryDischarge& d = discharge_[k];
      double* totals[4] = {&d.liquid_out, &d.liquid_in, &d.fines_out, &d.fines_in};
      for (int i = 0; i < 4; ++i) {
        // Kahan: carry the low-order bits the addition drops.
        double& c = discharge_carry_[k][i];
        const double y = step[k][i] - c, t = *totals[i] + y;
        c = (t - *totals[i]) - y;
        *totals[i] = t;
      }
    }
  };
  if (scene_.dim == 2)
    run(detail::Transport<2>{g});
  else
    run(detail::Transport<3>{g});

  for_chunks(points_.size(), [&](int, std::size_t b, std::size_t e) {
    detail::g2p_share(b, e, npp_, node_ids_.data(), weights_.data(), V, n, node_pore_.data(), node_liquid_.data(),
                      node_dliquid_.data(), points_.data(sf_.liquid_mass));
    if (fines_)
      detail::g2p_share(b, e, npp_, node_ids_.data(), weights_.data(), V, n, node_pore_.data(), node_fines_.data(),
                        node_dfines_.data(), points_.data(ef_.suspended_fines));
    // The momentum balance sees the pores full of the liquid the point
    // carries: n V rho_L, rho_L = c rho_s + (1 - c) rho_w. Not the carried
    // mass itself, which near a free surface inside the grid can pile up
    // (docs/two-phase.md, known defects).
    const double* ml = points_.data(sf_.liquid_mass);
    const double* rho_w = points_.data(ef_.water_density);
    double* rho = points_.data(sf_.liquid_density);
    double* moving = points_.data(sf_.moving_liquid_mass);
    const double* mf = fines_ ? points_.data(ef_.suspended_fines) : nullptr;
    const double* rho_s = points_.data(ef_.grain_density);
    double* c = fines_ ? points_.data(ef_.concentration) : nullptr;
    for (std::size_t p = b; p < e; ++p) {
      if (n[p] <= 0) continue;
      const double conc = mf ? detail::suspended_concentration(mf[p], ml[p], rho_s[p], rho_w[p]) : 0.0;
      if (c) c[p] = conc;
      rho[p] = conc * rho_s[p] + (1 - conc) * rho_w[p];
      moving[p] = n[p] * V[p] * rho[p];
    }
  });
}

MassLedger Simulation::mass_ledger() const {
  if (!saturated_) throw Error("mass_ledger: the scene has no saturated body");
  MassLedger l;
  l.time = time_;
  l.initial_solid = initial_solid_;
  l.initial_liquid = initial_liquid_;
  l.initial_fines = initial_fines_;
  const double* ms = points_.data(points_.core().mass);
  const double* ml = points_.data(sf_.liquid_mass);
  const double* n = points_.data(sf_.porosity);
  for (std::size_t p = 0; p < points_.size(); ++p) {
    if (n[p] <= 0) continue;  // the ledger covers the saturated bodies
    l.solid += ms[p];
    l.liquid += ml[p];
    if (!fines_) continue;
    l.skeleton_fines += points_.data(ef_.skeleton_fines)[p];
    l.suspended_fines += points_.data(ef_.suspended_fines)[p];
    l.eroded += points_.data(ef_.eroded_mass)[p];
  }
  l.boundaries = discharge_;
  return l;
}

void Simulation::write_ledger_row(std::ostream& out, bool header) const {
  if (header) {
    out << "time,solid,skeleton_fines,suspended_fines,liquid,eroded";
    for (const auto& d : discharge_)
      out << ",fines_out_" << d.face << ",fines_in_" << d.face << ",liquid_out_" << d.face << ",liquid_in_" << d.face;
    out << ",fines_imbalance,liquid_imbalance,solid_imbalance\n";
  }
  const MassLedger l = mass_ledger();
  out.precision(17);
  out << l.time << ',' << l.solid << ',' << l.skeleton_fines << ',' << l.suspended_fines << ',' << l.liquid << ','
      << l.eroded;
  for (const auto& d : l.boundaries) out << ',' << d.fines_out << ',' << d.fines_in << ',' << d.liquid_out << ',' << d.liquid_in;
  out << ',' << l.fines_imbalance() << ',' << l.liquid_imbalance() << ',' << l.solid_imbalance() << '\n';
}

}  // namespace suffuse
