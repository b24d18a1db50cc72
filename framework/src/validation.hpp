#pragma once
// Checks one JSON object against a parameter schema.
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

// Validates `node` (must be an object) against `schema`. Keys in `reserved`
// belong to someone else and are skipped. Every problem is appended to `out`;
// the returned Parameters hold the valid values and defaults.
Parameters validate_object(const Json& node, const ParameterSchema& schema,
                           const std::string& pointer, const std::string& declared_by, int dim,
                           std::vector<Diagnostic>& out, const std::set<std::string>& reserved = {});

}  // namespace suffuse::detail
