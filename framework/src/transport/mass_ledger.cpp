// The mass ledger of a saturated run: the totals of every species, from the
// points and the booked boundary discharges.
#include <cmath>
#include <ostream>

#include "transport/species_transport.hpp"

namespace suffuse {

namespace {
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

namespace detail {

MassLedger SpeciesTransport::mass_ledger(double time) const {
  MassLedger l;
  l.time = time;
  l.initial_solid = initial_solid_;
  l.initial_liquid = initial_liquid_;
  l.initial_fines = initial_fines_;
  const PointSet& pts = d_.points;
  const double* ms = pts.data(pts.core().mass);
  const double* ml = pts.data(m_.liquid_mass);
  const double* n = pts.data(m_.porosity);
  const double* skeleton = fines_ ? pts.data(fines_->skeleton_fines) : nullptr;
  const double* suspended = fines_ ? pts.data(fines_->suspended_fines) : nullptr;
  const double* eroded = fines_ ? pts.data(fines_->eroded_mass) : nullptr;
  const bool fines = fines_.has_value();
  const auto t = d_.exec.totals(pts.size(), 5, [&](std::size_t p, double* sum) {
    if (n[p] <= 0) return;  // the ledger covers the saturated bodies
    sum[0] += ms[p];
    sum[1] += ml[p];
    if (!fines) return;
    sum[2] += skeleton[p];
    sum[3] += suspended[p];
    sum[4] += eroded[p];
  });
  l.solid = t[0], l.liquid = t[1], l.skeleton_fines = t[2], l.suspended_fines = t[3], l.eroded = t[4];
  // What crossed the boundaries is summed over nodes, which every process
  // holds whole (communicator.hpp): the same total on each already.
  l.boundaries = discharge_;
  return l;
}

void SpeciesTransport::write_ledger_row(std::ostream& out, const MassLedger& l, bool header) const {
  if (header) {
    // Units in the header as every CSV of a run gives them (docs/outputs.md):
    // masses per metre of thickness in 2D, imbalances relative.
    const std::string mass = d_.dim() == 2 ? " [kg/m]" : " [kg]";
    out << "time [s]";
    for (const char* name : {"solid", "skeleton_fines", "suspended_fines", "liquid", "eroded"}) out << ',' << name << mass;
    for (const auto& d : discharge_)
      for (const char* name : {"fines_out_", "fines_in_", "liquid_out_", "liquid_in_"}) out << ',' << name << d.face << mass;
    out << ",fines_imbalance [-],liquid_imbalance [-],solid_imbalance [-]\n";
  }
  out.precision(17);
  out << l.time << ',' << l.solid << ',' << l.skeleton_fines << ',' << l.suspended_fines << ',' << l.liquid << ','
      << l.eroded;
  for (const auto& d : l.boundaries) out << ',' << d.fines_out << ',' << d.fines_in << ',' << d.liquid_out << ',' << d.liquid_in;
  out << ',' << l.fines_imbalance() << ',' << l.liquid_imbalance() << ',' << l.solid_imbalance() << '\n';
}

}  // namespace detail
}  // namespace suffuse
