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

// A fresh directory for one test, removed with its files at the end.
struct ScratchDirectory {
  std::filesystem::path path;
  explicit ScratchDirectory(const std::string& name) : path(std::filesystem::temp_directory_path() / name) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~ScratchDirectory() { std::filesystem::remove_all(path); }
  void copy_in(const std::filesystem::path& file, const std::string& as) const {
    std::filesystem::copy_file(file, path / as);
  }
};

// A plugin directory may hold other .so files (a dependency, a stray text
// file): they are skipped with a warning that names them, and the plugins load.
TEST(PluginLoading, DirectoryScanSkipsFilesThatAreNotPlugins) {
  const ScratchDirectory dir("suffuse_test_mixed_plugin_dir");
  dir.copy_in(plugin_dir / "good" / "libsuffuse_test_good.so", "libgood.so");
  dir.copy_in(plugin_dir / "no_entry" / "libsuffuse_test_no_entry.so", "libno_entry.so");
  { std::ofstream(dir.path / "notes.so") << "not a library\n"; }
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  testing::internal::CaptureStderr();
  loader.load_directory(dir.path);
  const std::string err = testing::internal::GetCapturedStderr();

  ASSERT_EQ(loader.libraries().size(), 1u);
  EXPECT_EQ(loader.libraries()[0].path.filename(), "libgood.so");
  EXPECT_NE(registry.find("phase/test_constant"), nullptr);
  const std::string dir_name = std::filesystem::canonical(dir.path).string();
  ASSERT_EQ(loader.warnings().size(), 2u);  // name order: libno_entry.so, notes.so
  const std::string& no_entry = loader.warnings()[0];
  EXPECT_NE(no_entry.find("skipped a file in plugin directory " + dir.path.string()), std::string::npos) << no_entry;
  EXPECT_NE(no_entry.find(dir_name + "/libno_entry.so is not a suffuse plugin: it exports no 'suffuse_plugin_entry'"),
            std::string::npos)
      << no_entry;
  const std::string& text_file = loader.warnings()[1];
  EXPECT_NE(text_file.find("cannot load plugin library " + dir_name + "/notes.so"), std::string::npos) << text_file;
  EXPECT_NE(text_file.find("file too short"), std::string::npos) << "the dynamic loader's reason: " << text_file;
  for (const std::string& w : loader.warnings())
    EXPECT_NE(err.find("suffuse: warning: " + w + "\n"), std::string::npos) << err;
}

// Only files that are no plugin at all are skipped: a real plugin library in a
// directory that fails a check (here: names another library registered) stops the run.
TEST(PluginLoading, DirectoryScanStillRefusesABadPluginLibrary) {
  const ScratchDirectory dir("suffuse_test_duplicate_plugin_dir");
  dir.copy_in(plugin_dir / "good" / "libsuffuse_test_good.so", "liba.so");
  dir.copy_in(plugin_dir / "good" / "libsuffuse_test_good.so", "libb.so");
  const std::string m = load_error(dir.path);
  EXPECT_NE(m.find("is registered twice: by " + std::filesystem::canonical(dir.path / "liba.so").string()),
            std::string::npos)
      << m;
}

// A library named explicitly must load: there the same files are errors.
TEST(PluginLoading, ExplicitFileThatIsNotAPluginIsStillAnError) {
  const ScratchDirectory dir("suffuse_test_explicit_not_plugin");
  { std::ofstream(dir.path / "notes.so") << "not a library\n"; }
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  EXPECT_THROW(loader.load_path(dir.path / "notes.so"), suffuse::Error);
  EXPECT_THROW(loader.load_library(plugin_dir / "no_entry" / "libsuffuse_test_no_entry.so"), suffuse::Error);
  EXPECT_TRUE(loader.warnings().empty());
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
