// bc/water_level: still water outside the bodies, its surface at a level
// that may follow a hydrograph: a river on a levee's riverside slope, a
// ditch at its landside toe, a flood over the ground. Below the level the
// water presses gamma_w (level - elevation) on the bodies' surface, on
// slopes as on flat ground, on the skeleton and on the pore liquid; the
// core integrates that pressure (docs/boundaries.md, Water levels). This
// condition says only where the water stands, and when.
#include <sstream>
#include <string>
#include <suffuse/plugin.hpp>
#include <vector>

namespace {

std::string text(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}

class WaterLevelBC final : public suffuse::BoundaryCondition {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.time_series("level").with_unit("m").doc(
        "Elevation of the water's surface (y in 2D, z in 3D): a number, or in time a table [[t, level], ...] or a "
        "CSV file (a hydrograph: \"time [h], level [m]\"; docs/boundaries.md)");
    s.number("from").with_unit("m").may_be_absent().doc(
        "Where along x this level holds, from (default: from the grid's start). Beyond the outermost levels of a "
        "scene the nearest one holds, and between two the level is interpolated along x, so that it is "
        "continuous through the bodies: put the gap where the surface is above both (a crest), and give a dry "
        "side its own level at or below its ground (a ditch, the ground water)");
    s.number("to").with_unit("m").may_be_absent().doc("Where along x this level holds, to (default: to the grid's end)");
    s.number("unit_weight").with_unit("N/m^3").above(0).fallback(9810.0).doc(
        "Unit weight of the water gamma_w (the same for every water level of a scene)");
    return s;
  }

  static std::vector<suffuse::ParameterIssue> check(const suffuse::Parameters& p, int) {
    if (p.has("from") && p.has("to") && !(p.number("from") < p.number("to")))
      return {{"to", "empty stretch", "to > from (" + text(p.number("from")) + ")", text(p.number("to"))}};
    return {};
  }

  explicit WaterLevelBC(const suffuse::PluginArgs& a) : level_(a.params.time_series("level")) {
    water_.unit_weight = a.params.number("unit_weight");
    if (a.params.has("from")) water_.from = a.params.number("from");
    if (a.params.has("to")) water_.to = a.params.number("to");
  }

  void setup(const suffuse::GridGeometry&) override {}

  std::optional<suffuse::StandingWater> standing_water(double time) const override {
    suffuse::StandingWater w = water_;
    w.level = level_(time);
    return w;
  }

 private:
  suffuse::TimeFunction level_;
  suffuse::StandingWater water_;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::BoundaryCondition, WaterLevelBC>(
      "bc/water_level",
      "Still water at a level (constant or a hydrograph) pressing on the submerged surface of saturated bodies");
}
