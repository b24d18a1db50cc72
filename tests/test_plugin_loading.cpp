// The plugin loader: a good library registers, bad ones are refused with
// messages that say why.
#include <gtest/gtest.h>

#include <fstream>
#include <suffuse/error.hpp>
#include <suffuse/plugin_loader.hpp>

namespace {

const std::filesystem::path plugin_dir = SUFFUSE_TEST_PLUGIN_DIR;

std::string load_error(const std::filesystem::path& path) {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  try {
    loader.load_path(path);
  } catch (const suffuse::Error& e) {
    return e.what();
  }
  return "";
}

TEST(PluginLoading, GoodLibraryRegistersAllItsPlugins) {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  loader.load_path(plugin_dir / "good");
  ASSERT_EQ(loader.libraries().size(), 1u);
  const auto& lib = loader.libraries()[0];
  EXPECT_EQ(lib.path.filename(), "libsuffuse_test_good.so");
  EXPECT_EQ(lib.abi_major, suffuse::abi_major);
  EXPECT_EQ(lib.plugins, (std::vector<std::string>{"erosion/test_none", "phase/test_constant"}));

  const suffuse::PluginInfo* info = registry.find("phase/test_constant");
  ASSERT_NE(info, nullptr);
  EXPECT_EQ(info->kind, suffuse::PluginKind::Phase);
  EXPECT_EQ(info->library, lib.path.string());
  EXPECT_EQ(info->schema().params().size(), 1u);

  suffuse::Parameters params({{"density", 1234.0}});
  auto phase = registry.create<suffuse::Phase>("phase/test_constant", {params, 2, "/materials/x"});
  EXPECT_EQ(phase->density(), 1234.0);
  // Asking for the wrong kind is an error, not a bad cast.
  EXPECT_THROW(registry.create<suffuse::Writer>("phase/test_constant", {params, 2, "/x"}), suffuse::Error);
}

TEST(PluginLoading, LoadingTwiceIsHarmless) {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  loader.load_path(plugin_dir / "good");
  loader.load_path(plugin_dir / "good" / "libsuffuse_test_good.so");
  EXPECT_EQ(loader.libraries().size(), 1u);
}

TEST(PluginLoading, DuplicateNamesFromTwoLibrariesAreRefused) {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  loader.load_path(plugin_dir / "good");
  // Same plugin name from a second registration: a hard error naming both sources.
  suffuse::PluginInfo info = *registry.find("phase/test_constant");
  registry.set_current_library("/elsewhere/libother.so");
  try {
    registry.add_info(info);
    FAIL() << "duplicate accepted";
  } catch (const suffuse::Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("plugin 'phase/test_constant' is registered twice"), std::string::npos) << m;
    EXPECT_NE(m.find("libsuffuse_test_good.so"), std::string::npos) << m;
    EXPECT_NE(m.find("/elsewhere/libother.so"), std::string::npos) << m;
  }
}

TEST(PluginLoading, LibraryWithoutEntryPointIsRefused) {
  const std::string m = load_error(plugin_dir / "no_entry" / "libsuffuse_test_no_entry.so");
  EXPECT_NE(m.find("libsuffuse_test_no_entry.so is not a suffuse plugin: it exports no "
                   "'suffuse_plugin_entry' entry point"),
            std::string::npos)
      << m;
}

TEST(PluginLoading, OtherAbiMajorVersionIsRefused) {
  const std::string m = load_error(plugin_dir / "wrong_abi");
  const std::string expected = "libsuffuse_test_wrong_abi.so was built for plugin ABI " +
                               std::to_string(suffuse::abi_major + 1) + ".0 but this suffuse (" +
                               suffuse::framework_version + ") has plugin ABI " + std::to_string(suffuse::abi_major) +
                               "." + std::to_string(suffuse::abi_minor) + ": rebuild the plugin";
  EXPECT_NE(m.find(expected), std::string::npos) << m;
}

TEST(PluginLoading, FileThatIsNotALibraryGivesTheDlopenMessage) {
  const std::filesystem::path fake = std::filesystem::temp_directory_path() / "suffuse_not_a_library.so";
  { std::ofstream(fake) << std::string(4096, 'x'); }  // long enough to reach the header check
  const std::string m = load_error(fake);
  EXPECT_NE(m.find("cannot load plugin library " + std::filesystem::canonical(fake).string()), std::string::npos) << m;
  // The real reason from the dynamic loader, not a generic failure.
  EXPECT_NE(m.find("invalid ELF header"), std::string::npos) << m;
  std::filesystem::remove(fake);
}

TEST(PluginLoading, MissingPathIsAnError) {
  const std::string m = load_error("/nonexistent/suffuse/plugins");
  EXPECT_EQ(m, "plugin path /nonexistent/suffuse/plugins does not exist");
}

TEST(PluginLoading, BundledPluginsAreFound) {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  for (const auto& p : suffuse::PluginLoader::default_search_path()) loader.load_path(p);
  for (const char* name : {"shape/linear", "phase/linear_elastic", "bc/velocity", "writer/vtk_particles"})
    EXPECT_NE(registry.find(name), nullptr) << name;
}

}  // namespace

namespace {

TEST(PluginLoading, SecondLoaderOnTheSameRegistryAddsNothing) {
  suffuse::Registry registry;
  suffuse::PluginLoader first(registry), second(registry);
  first.load_path(plugin_dir / "good");
  EXPECT_NO_THROW(second.load_path(plugin_dir / "good"));
  EXPECT_EQ(registry.all().size(), 2u);
}

}  // namespace

namespace {

// ParameterSchema::complete, for plugin unit tests: what a scene would accept.
TEST(PluginLoading, SchemaCompletesParametersGivenInCode) {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  loader.load_directory(suffuse::PluginLoader::bundled_plugin_directory());
  const suffuse::ParameterSchema schema = registry.find("erosion/fines_limited")->schema();
  const suffuse::Parameters p = schema.complete({{"lambda", 2.0}});
  EXPECT_EQ(p.number("lambda"), 2.0);
  EXPECT_EQ(p.number("critical_gradient"), 0.0) << "the default is filled in";
  EXPECT_THROW(schema.complete({}), suffuse::Error);
  EXPECT_THROW(schema.complete({{"lambda", -1.0}}), suffuse::Error);
  EXPECT_THROW(schema.complete({{"lambda", 1.0}, {"lamda", 1.0}}), suffuse::Error);
  EXPECT_THROW(schema.complete({{"lambda", std::string("one")}}), suffuse::Error);
}

}  // namespace
