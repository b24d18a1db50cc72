#pragma once
// Errors found while validating a scene. All of them are collected and
// reported together, each naming its JSON pointer.
#include <string>
#include <vector>

#include "suffuse/error.hpp"

namespace suffuse {

struct Diagnostic {
  std::string pointer;      // JSON pointer, e.g. /materials/sand/youngs_modulus
  std::string problem;      // e.g. "value out of range", "unknown key"
  std::string expected;     // e.g. "number > 0 [Pa]"
  std::string found;        // e.g. "-5"
  std::string declared_by;  // plugin or core section that declared the parameter

  std::string message() const;
};

class SceneError : public Error {
 public:
  SceneError(std::string scene, std::vector<Diagnostic> diagnostics);
  const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }

 private:
  std::vector<Diagnostic> diagnostics_;
};

}  // namespace suffuse
