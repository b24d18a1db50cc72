// Unit test of the phase: load the built plugin as suffuse does, give it one
// point whose eroded fraction grew over the step, and compare the eigenstrain
// and the stress with the closed form.
#include <gtest/gtest.h>

#include <suffuse/error.hpp>
#include <suffuse/plugin_loader.hpp>
#include <vector>

TEST(ErodingElastic, SofteningRelaxesTheStressThroughTheEigenstrain) {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  loader.load_library(PLUGIN_FILE);
  const suffuse::PluginInfo* info = registry.find("phase/eroding_elastic");
  ASSERT_NE(info, nullptr);
  // complete(): checks the values against the schema and fills in the defaults, as a scene would.
  const suffuse::Parameters params =
      info->schema().complete({{"density", 2650.0}, {"youngs_modulus", 1e7}, {"poisson_ratio", 0.25}});
  // The core refuses scenes without these fields before building anything.
  const std::vector<std::string> needs = info->required_fields(params, 2);
  EXPECT_EQ(needs, (std::vector<std::string>{"eroded_fraction", "eroded_fraction_increment"}));

  // One point, as the core lays it out: its fields, then the phase's look-up.
  suffuse::PointSet points(2);
  const auto fer = points.add_field({"eroded_fraction", suffuse::FieldKind::Scalar, "-", "", false});
  const auto dfer = points.add_field({"eroded_fraction_increment", suffuse::FieldKind::Scalar, "-", "", false});
  auto phase = registry.create<suffuse::Phase>("phase/eroding_elastic", {params, 2, "/materials/sand"});
  phase->add_fields(points);
  points.append(1);
  const double sigma[6] = {-1000, -2000, -500, 0, 0, 300};
  for (int c = 0; c < 6; ++c) points.data(points.core().stress)[c] = sigma[c];
  // The default softening a = 5: f_er 0 -> 0.1 halves E (velocity gradient zero).
  points.data(fer)[0] = 0.1;
  points.data(dfer)[0] = 0.1;
  const suffuse::StressBatch batch{points, {0, 1}, 1e-3, {}};
  std::vector<double> eigenstrain(6);
  ASSERT_TRUE(phase->writes_eigenstrain());
  phase->eigenstrain(batch, eigenstrain);
  // E_old / E_new - 1 = 1: the eigenstrain is the elastic strain S(E_0) sigma.
  const double E0 = 1e7, nu = 0.25, tr = sigma[0] + sigma[1] + sigma[2];
  for (int c = 0; c < 6; ++c)
    EXPECT_NEAR(eigenstrain[c], ((1 + nu) * sigma[c] - (c < 3 ? nu * tr : 0.0)) / E0, 1e-18) << "component " << c;
  // Held in place, the point keeps its strain: the halved stiffness carries half the stress.
  phase->update_stress(suffuse::StressBatch{points, {0, 1}, 1e-3, eigenstrain});
  for (int c = 0; c < 6; ++c)
    EXPECT_NEAR(points.data(points.core().stress)[c], 0.5 * sigma[c], 1e-9) << "component " << c;
}

TEST(ErodingElastic, SchemaRejectsBadParameters) {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  loader.load_library(PLUGIN_FILE);
  const suffuse::ParameterSchema schema = registry.find("phase/eroding_elastic")->schema();
  EXPECT_THROW(schema.complete({{"density", 2650.0}}), suffuse::Error);  // youngs_modulus is required
  EXPECT_THROW(schema.complete({{"density", 2650.0}, {"youngs_modulus", 1e7}, {"residual_stiffness", 0.0}}),
               suffuse::Error);  // above 0
  EXPECT_THROW(schema.complete({{"density", 2650.0}, {"youngs_modulus", 1e7}, {"softning", 1.0}}),
               suffuse::Error);  // unknown key
}
