// erosion/first_order: a minimal erosion-law plugin for suffuse, to copy.
//
// Law: first-order kinetics of the erodible fines, whatever the flow,
//   n_e = k (1 - n) (f_c - f_c_inf)          [1/s]
// with k the rate constant [1/s]. (1 - n) f_c is the volume of fines per
// volume of soil, so the fines above f_c_inf decay as exp(-(1 - f_c_inf) k t).
// It is a stand-in for your own law: erosion/fines_limited is the same with k
// replaced by lambda |q|.
//
// What a law does and does not do (docs/plugins.md has the whole guide):
// - rate() gets a batch of points as spans of equal length and fills
//   batch.rate. It is called from several threads at once on different
//   batches: keep it const, keep no mutable state.
// - The core moves the mass, limits the step so that f_c never drops below
//   f_c_inf, updates the porosity and the permeability, and keeps the ledger.
#include <suffuse/plugin.hpp>

namespace {

class FirstOrderErosion final : public suffuse::ErosionLaw {
 public:
  // Every parameter is declared once, with its unit, range and meaning. The
  // core checks scenes against it (unknown keys are errors) and prints it in
  // `suffuse describe erosion/first_order`.
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.number("rate_constant").with_unit("1/s").at_least(0).doc("Rate constant k of the first-order decay of the erodible fines");
    return s;
  }

  // Parameters are read once, into plain members: no lookups in rate().
  explicit FirstOrderErosion(const suffuse::PluginArgs& args) : k_(args.params.number("rate_constant")) {}

  void rate(const suffuse::ErosionBatch& b) const override {
    for (std::size_t p = 0; p < b.rate.size(); ++p)
      b.rate[p] = k_ * (1 - b.porosity[p]) * (b.fines_content[p] - b.ultimate_fines_content[p]);
  }

 private:
  double k_;
};

}  // namespace

// The library's entry point: registers its plugins by name. One library may
// register several plugins of any kinds (a law and its boundary condition...).
SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::ErosionLaw, FirstOrderErosion>(
      "erosion/first_order", "First-order decay of the erodible fines: n_e = k (1-n) (f_c - f_c_inf)");
}
