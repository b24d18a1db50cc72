// The source tree keeps the shape framework/src/README.md gives it: each part
// of the core includes only the parts its row of the README's table names,
// the figures never include the command line, and no source grows past 600
// lines (800 with its header), so that a file stays one idea. The map and
// the steps docs/architecture.md shows are the source's.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace fs = std::filesystem;
using suffuse::test::slurp;

namespace {

const fs::path source_dir = SUFFUSE_SOURCE_DIR;

// Part -> the parts it may include, read from the README's table: a row
// "| `mpm/` | what it owns | parallel |"; "nothing private" is none, "every
// part above" every part of the rows before it.
std::map<std::string, std::set<std::string>> documented_layers() {
  std::map<std::string, std::set<std::string>> layers;
  std::vector<std::string> above;
  std::istringstream readme(slurp(source_dir / "framework/src/README.md"));
  const std::regex row(R"(^\| `([a-z_]+)/` \|[^|]*\| ([^|]*) \|$)");
  for (std::string line; std::getline(readme, line);) {
    std::smatch m;
    if (!std::regex_match(line, m, row)) continue;
    std::set<std::string> allowed;
    const std::string rule = m[2];
    if (rule == "every part above") {
      allowed.insert(above.begin(), above.end());
    } else if (rule != "nothing private") {
      std::istringstream parts(rule);
      for (std::string p; std::getline(parts, p, ',');) {
        p.erase(0, p.find_first_not_of(' '));
        allowed.insert(p);
      }
    }
    layers[m[1]] = allowed;
    above.push_back(m[1]);
  }
  return layers;
}

std::vector<fs::path> sources_under(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.path().extension() == ".cpp" || e.path().extension() == ".hpp") files.push_back(e.path());
  return files;
}

// Part -> the parts whose private headers it includes.
std::map<std::string, std::set<std::string>> include_graph() {
  std::map<std::string, std::set<std::string>> graph;
  const std::regex include(R"(#include "([a-z_]+)/[a-z_0-9]+\.hpp")");
  for (const auto& dir : fs::directory_iterator(source_dir / "framework/src")) {
    if (!dir.is_directory()) continue;
    const std::string part = dir.path().filename();
    graph[part];
    for (const fs::path& file : sources_under(dir.path())) {
      const std::string text = slurp(file);
      for (auto it = std::sregex_iterator(text.begin(), text.end(), include); it != std::sregex_iterator(); ++it)
        if ((*it)[1] != part && (*it)[1] != "suffuse") graph[part].insert((*it)[1]);
    }
  }
  return graph;
}

// The fenced blocks of a Markdown file in a language ("mermaid", "cpp").
std::vector<std::string> fenced_blocks(const std::string& text, const std::string& language) {
  std::vector<std::string> blocks;
  const std::string open = "```" + language + "\n";
  for (std::size_t at = text.find(open); at != std::string::npos; at = text.find(open, at)) {
    const std::size_t begin = at + open.size(), end = text.find("```", begin);
    blocks.push_back(text.substr(begin, end - begin));
    at = end;
  }
  return blocks;
}

std::size_t line_count(const fs::path& file) {
  const std::string text = slurp(file);
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

}  // namespace

TEST(ModuleLayout, EachPartOfTheCoreIncludesOnlyThePartsItsReadmeRowNames) {
  const auto layers = documented_layers();
  ASSERT_GE(layers.size(), 10u) << "the table of framework/src/README.md was not read";
  for (const auto& [part, used] : include_graph()) {
    ASSERT_TRUE(layers.count(part)) << "framework/src/" << part << "/ has no row in framework/src/README.md";
    for (const std::string& u : used)
      EXPECT_TRUE(layers.at(part).count(u)) << "framework/src/" << part << "/ includes a header of " << u
                                            << "/, which its row in framework/src/README.md does not allow";
  }
}

TEST(ModuleLayout, TheMapOfArchitectureMdIsTheIncludeGraph) {
  const auto blocks = fenced_blocks(slurp(source_dir / "docs/architecture.md"), "mermaid");
  ASSERT_EQ(blocks.size(), 1u) << "one map in docs/architecture.md";
  std::map<std::string, std::set<std::string>> drawn;
  std::istringstream lines(blocks[0]);
  const std::regex edge(R"(^\s*([a-z_]+) --> ([a-z_]+)\s*$)"), node(R"(^\s*([a-z_]+)\s*$)");
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (std::regex_match(line, m, edge)) {
      drawn[m[1]].insert(m[2]);
      drawn[m[2]];
    } else if (std::regex_match(line, m, node)) {
      drawn[m[1]];
    }
  }
  EXPECT_EQ(drawn, include_graph()) << "redraw the map of docs/architecture.md from the includes";
}

TEST(ModuleLayout, TheStepsOfArchitectureMdAreTheSource) {
  const std::string source = slurp(source_dir / "framework/src/run/simulation.cpp");
  std::size_t functions = 0;
  for (const std::string& block : fenced_blocks(slurp(source_dir / "docs/architecture.md"), "cpp")) {
    if (block.find("void Simulation::step") == std::string::npos) continue;
    // Each function of the block (blocks separate them by a blank line).
    for (std::size_t begin = 0; begin < block.size();) {
      std::size_t end = block.find("\n\n", begin);
      if (end == std::string::npos) end = block.size();
      const std::string function = block.substr(begin, end - begin);
      EXPECT_NE(source.find(function), std::string::npos) << "not in run/simulation.cpp:\n" << function;
      ++functions;
      begin = end + 2;
    }
  }
  EXPECT_GE(functions, 4u) << "step, locate_points, step_explicit and step_quasi_static are shown";
}

TEST(ModuleLayout, TheFiguresNeverIncludeTheCommandLine) {
  std::set<std::string> cli_headers;
  for (const fs::path& f : sources_under(source_dir / "apps/cli"))
    if (f.extension() == ".hpp") cli_headers.insert(f.filename());
  ASSERT_FALSE(cli_headers.empty());
  for (const fs::path& file : sources_under(source_dir / "apps/figures")) {
    const std::string text = slurp(file);
    for (const std::string& h : cli_headers)
      EXPECT_EQ(text.find("#include \"" + h + "\""), std::string::npos)
          << fs::relative(file, source_dir).string() << " includes apps/cli/" << h;
  }
}

TEST(ModuleLayout, NoSourcePasses600LinesNorWithItsHeader800) {
  for (const char* top : {"framework", "plugins", "apps"}) {
    for (const fs::path& file : sources_under(source_dir / top)) {
      const std::size_t lines = line_count(file);
      EXPECT_LE(lines, 600u) << fs::relative(file, source_dir).string();
      if (file.extension() != ".cpp") continue;
      fs::path header = file;
      header.replace_extension(".hpp");
      if (fs::exists(header)) {
        EXPECT_LE(lines + line_count(header), 800u)
            << fs::relative(file, source_dir).string() << " with its header";
      }
    }
  }
}
