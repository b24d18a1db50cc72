// Inputs the scene fuzzer (fuzz/fuzz_scene.cpp) found to crash, hang or trip
// a sanitizer, replayed through parse_scene in every build: each must now be
// accepted or refused with an exception, fast. See docs/robustness.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "test_support.hpp"

namespace fs = std::filesystem;
using namespace suffuse;

namespace {

std::vector<fs::path> regression_inputs() {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(test::source_dir() / "tests" / "fuzz_regressions"))
    if (e.is_regular_file() && e.path().filename() != "README.md") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

TEST(FuzzRegressions, EveryFoundInputIsAcceptedOrRefusedWithAMessage) {
  const std::vector<fs::path> files = regression_inputs();
  if (files.empty()) GTEST_SKIP() << "no input in tests/fuzz_regressions yet";
  Registry registry;
  PluginLoader loader(registry);
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.filename().string());
    std::ifstream in(file, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    const auto start = std::chrono::steady_clock::now();
    try {
      // As the fuzzer runs it: relative paths resolve like the example scenes'.
      parse_scene(text.str(), "fuzz.json", test::source_dir() / "share" / "scenes", registry, loader);
    } catch (const std::exception& e) {
      EXPECT_STRNE(e.what(), "");
    }
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
  }
}
