#pragma once
// Checks one JSON object against a parameter schema.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "suffuse/diagnostics.hpp"
#include "suffuse/parameters.hpp"

namespace suffuse::detail {

std::string pointer_append(const std::string& pointer, const std::string& key);
using Json = nlohmann::ordered_json;  // keeps the file's key order

std::string show(const Json& value);  // short text of a found value

// Limits on a scene file, checked before it is parsed: no real scene comes
// near them, and past them the parser (deep nesting) or memory (size) would
// fail without a message.
inline constexpr std::size_t max_scene_bytes = 64u << 20;  // 64 MiB
inline constexpr int max_scene_depth = 64;                 // arrays and objects nested

// Parses a scene's text; throws SceneError naming `name` for text that is too
// large, nested too deeply or not JSON.
Json parse_scene_text(const std::string& text, const std::string& name);
// Reads a scene file, refusing one larger than max_scene_bytes before reading it.
std::string read_scene_file(const std::filesystem::path& file);

// Validates `node` (must be an object) against `schema`. Keys in `reserved`
// belong to someone else and are skipped. Every problem is appended to `out`;
// the returned Parameters hold the valid values and defaults. Files the
// values name (a time series' CSV) are relative to base_dir.
Parameters validate_object(const Json& node, const ParameterSchema& schema,
                           const std::string& pointer, const std::string& declared_by, int dim,
                           std::vector<Diagnostic>& out, const std::set<std::string>& reserved = {},
                           const std::filesystem::path& base_dir = {});

}  // namespace suffuse::detail
