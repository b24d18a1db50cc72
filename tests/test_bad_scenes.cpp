// The corpus of bad scenes (tests/bad_scenes/): each file must be refused
// with exactly the errors listed for it in expected_errors.json, as
// `suffuse validate` prints them, and nothing else: wrong types, zero and
// negative moduli and densities, porosity outside (0, 1), fines contents out
// of order, bodies outside the grid, bad cell counts, unknown and duplicate
// names and keys, unknown plugins, numbers that are not finite, empty files,
// non-JSON, other roots, invalid UTF-8, deep nesting.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <suffuse/diagnostics.hpp>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/scene.hpp>

#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

const fs::path corpus = suffuse::test::source_dir() / "tests/bad_scenes";

std::vector<std::string> errors_of(const fs::path& file) {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  try {
    suffuse::load_scene(file, registry, loader);
  } catch (const suffuse::SceneError& e) {
    std::vector<std::string> lines;
    for (const suffuse::Diagnostic& d : e.diagnostics()) lines.push_back(d.message());
    return lines;
  }
  return {"(accepted)"};
}

}  // namespace

TEST(BadScenes, EachIsRefusedWithExactlyItsErrors) {
  const nlohmann::json expected = suffuse::test::read_json(corpus / "expected_errors.json");
  std::set<std::string> files;
  for (const auto& entry : fs::directory_iterator(corpus))
    if (entry.path().extension() == ".json" && entry.path().filename() != "expected_errors.json")
      files.insert(entry.path().filename().string());
  EXPECT_GE(files.size(), 40u) << "the corpus the issue asks for";
  for (const std::string& file : files) {
    ASSERT_TRUE(expected.contains(file)) << file << " has no expected errors in expected_errors.json";
    EXPECT_EQ(errors_of(corpus / file), expected[file].get<std::vector<std::string>>()) << file;
  }
  EXPECT_EQ(expected.size(), files.size()) << "every expectation has its file";
}
