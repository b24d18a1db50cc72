#include "suffuse/diagnostics.hpp"

namespace suffuse {

std::string Diagnostic::message() const {
  std::string m = (pointer.empty() ? std::string("/") : pointer) + ": " + problem;
  if (!expected.empty()) m += "; expected " + expected;
  if (!found.empty()) m += ", found " + found;
  if (!declared_by.empty()) m += " (declared by " + declared_by + ")";
  return m;
}

namespace {
std::string summary(const std::string& scene, const std::vector<Diagnostic>& diagnostics) {
  std::string m = "scene " + scene + " is invalid (" + std::to_string(diagnostics.size()) +
                  (diagnostics.size() == 1 ? " error):" : " errors):");
  for (const Diagnostic& d : diagnostics) m += "\n  " + d.message();
  return m;
}
}  // namespace

SceneError::SceneError(std::string scene, std::vector<Diagnostic> diagnostics)
    : Error(summary(scene, diagnostics)), diagnostics_(std::move(diagnostics)) {}

}  // namespace suffuse
