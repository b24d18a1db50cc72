// Unit test of the law: load the built plugin as suffuse does, create the law
// from parameters, and compare rate() with the formula on a batch.
#include <gtest/gtest.h>

#include <suffuse/error.hpp>
#include <suffuse/plugin_loader.hpp>
#include <vector>

TEST(FirstOrderErosion, RateFollowsTheFormula) {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  loader.load_library(PLUGIN_FILE);

  const suffuse::PluginInfo* info = registry.find("erosion/first_order");
  ASSERT_NE(info, nullptr);
  // complete(): checks the values against the law's schema and fills in the
  // defaults, as a scene would.
  const suffuse::Parameters params = info->schema().complete({{"rate_constant", 0.5}});
  auto law = registry.create<suffuse::ErosionLaw>("erosion/first_order", {params, 2, "/materials/sand/erosion"});

  const std::vector<double> n = {0.3, 0.4, 0.35}, fc = {0.2, 0.1, 0.05}, f_inf = {0.05, 0.05, 0.05};
  const std::vector<double> zero(3, 0.0);
  std::vector<double> rate(3, -1.0);
  law->rate({.porosity = n,
             .fines_content = fc,
             .ultimate_fines_content = f_inf,
             .concentration = zero,
             .darcy_flux = zero,
             .hydraulic_gradient = zero,
             .rate = rate});
  for (std::size_t p = 0; p < rate.size(); ++p)
    EXPECT_DOUBLE_EQ(rate[p], 0.5 * (1 - n[p]) * (fc[p] - f_inf[p])) << "point " << p;
  EXPECT_EQ(rate[2], 0.0) << "no erodible fines left, no erosion";
}

TEST(FirstOrderErosion, SchemaRejectsBadParameters) {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  loader.load_library(PLUGIN_FILE);
  const suffuse::ParameterSchema schema = registry.find("erosion/first_order")->schema();
  EXPECT_THROW(schema.complete({}), suffuse::Error);                              // rate_constant is required
  EXPECT_THROW(schema.complete({{"rate_constant", -1.0}}), suffuse::Error);       // at least 0
  EXPECT_THROW(schema.complete({{"rate_konstant", 0.5}}), suffuse::Error);        // unknown key
}
