// A body's gradation: its PSD, from a file beside the scene or inline, the
// internal-stability criteria on it, and the erodible fines content it gives.
// Read while the scene is validated: nothing is allocated or written for it.
#include "scene/scene_reader.hpp"

namespace suffuse::detail {

namespace {

std::optional<Gradation> read_points(SceneReader& r, const Parameters& b, const std::string& ptr) {
  const std::vector<double>& flat = b.vector("gradation_points");  // row after row (validated: 2 columns)
  std::vector<std::array<double, 2>> rows;
  for (std::size_t k = 0; k + 1 < flat.size(); k += 2) rows.push_back({flat[k], flat[k + 1]});
  if (auto p = check_gradation(rows)) {
    std::string at = ptr + "/gradation_points";
    if (p->column >= 0) at.append("/").append(std::to_string(p->row)).append("/").append(std::to_string(p->column));
    r.error(at, p->problem, p->expected, p->found, "core (body)");
    return std::nullopt;
  }
  return Gradation(rows, ptr + "/gradation_points");
}

std::optional<Gradation> read_file(SceneReader& r, const Parameters& b, const std::string& ptr) {
  std::filesystem::path file = b.string("gradation");
  if (file.is_relative()) file = r.base_dir / file;
  try {
    return read_gradation_file(file);
  } catch (const Error& e) {  // reported with the scene's other problems, at the key that names the file
    r.error(ptr + "/gradation", "unreadable PSD file", "a PSD file as docs/gradation.md describes", e.what(),
            "core (body)");
    return std::nullopt;
  }
}

}  // namespace

void read_gradation(SceneReader& r, const Json& node, const Parameters& b, const std::string& ptr, BodySpec& body) {
  const bool from_gradation = b.has("fines_content_from_gradation") && b.boolean("fines_content_from_gradation");
  if (b.has("gradation") && b.has("gradation_points")) {
    r.error(ptr + "/gradation_points", "two gradations", "either \"gradation\" (a file) or \"gradation_points\"",
            "both", "core (body)");
    return;
  }
  std::optional<Gradation> g;
  if (b.has("gradation")) g = read_file(r, b, ptr);
  else if (b.has("gradation_points")) g = read_points(r, b, ptr);
  if (g) {
    body.gradation_source = g->source();
    body.internal_stability = assess_internal_stability(*g);
  }
  if (!from_gradation) return;
  const std::string at = ptr + "/fines_content_from_gradation";
  if (!b.has("gradation") && !b.has("gradation_points")) {
    r.error(at, "fines content from a gradation the body does not have", "a \"gradation\" or \"gradation_points\"",
            "neither", "core (body)");
  } else if (node.is_object() && node.contains("fines_content")) {
    r.error(ptr + "/fines_content", "two fines contents", "either fines_content or fines_content_from_gradation",
            "both", "core (body)");
  } else if (!b.has("liquid")) {
    r.error(at, "fines in a dry body", "false without \"liquid\"", "true", "core (body)");
  } else if (body.internal_stability) {
    body.fines_content_from_gradation = true;
    body.fines_content = body.internal_stability->erodible_fines;
  }
}

}  // namespace suffuse::detail
