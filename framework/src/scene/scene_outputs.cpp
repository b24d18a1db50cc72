// Outputs: writer plugin nodes, with the interval the core reads from each.
#include <algorithm>
#include <cctype>

#include "scene/scene_reader.hpp"

namespace suffuse::detail {

namespace {

ParameterSchema output_schema() {
  ParameterSchema s;
  s.number("interval").with_unit("s").above(0).may_be_absent().doc(
      "Simulation time between frames; absent: end time / 20 (writer/csv_probe: / 200). The initial and final "
      "states are always written");
  s.string("name").may_be_absent().doc(
      "Names this output's files, <scene>.<name>...: letters, digits, _ and -, unique among the outputs; absent: "
      "<scene>, or <scene>_<index in /outputs> when the scene has several writers of its type");
  return s;
}

// A name becomes part of file names: no path separators, no clash.
void check_output_name(SceneReader& r, const Scene& scene, const std::string& name, const std::string& ptr) {
  const bool plain = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
  if (!plain) r.error(ptr, "not a file-name part", "letters, digits, _ and -", "\"" + name + "\"", "core (output)");
  for (std::size_t k = 0; k < scene.outputs.size(); ++k)
    if (scene.outputs[k].name == name)
      r.error(ptr, "duplicate output name", "a name no other output has", "\"" + name + "\", as /outputs/" +
              std::to_string(k) + "/name", "core (output)");
}

void read_outputs(SceneReader& r, Scene& scene) {
  if (!r.root.contains("outputs")) return;
  const Json& outputs = r.root["outputs"];
  if (!outputs.is_array()) {
    r.error("/outputs", "wrong type", "array of writer nodes", show(outputs), "core (scene)");
    return;
  }
  const ParameterSchema core = output_schema();
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const std::string ptr = "/outputs/" + std::to_string(i);
    OutputSpec out;
    std::set<std::string> core_keys;
    for (const Param& p : core.params()) core_keys.insert(p.name);
    out.writer = r.plugin_node(outputs[i], ptr, PluginKind::Writer, core_keys);
    if (outputs[i].is_object()) {
      // Unknown keys are the plugin's to report: the core checks only its own.
      std::set<std::string> others;
      for (const auto& [k, v] : outputs[i].items())
        if (!core_keys.count(k)) others.insert(k);
      Parameters o = validate_object(outputs[i], core, ptr, "core (output)", r.dim, r.diags, others);
      out.interval = o.maybe_number("interval");
      if (o.has("name")) out.name = o.string("name");
    }
    if (out.name) check_output_name(r, scene, *out.name, ptr + "/name");
    scene.outputs.push_back(std::move(out));
  }
}

}  // namespace

SceneSection outputs_section() {
  return {"outputs", "output",
          "Keys every writer node accepts besides its plugin's own (an entry of /outputs)",
          output_schema, read_outputs};
}

}  // namespace suffuse::detail

namespace suffuse {

std::string output_basename(const Scene& scene, std::size_t output) {
  const OutputSpec& out = scene.outputs[output];
  if (out.name) return scene.name + "." + *out.name;
  const auto same_type = std::count_if(scene.outputs.begin(), scene.outputs.end(),
                                       [&](const OutputSpec& o) { return o.writer.type == out.writer.type; });
  return same_type == 1 ? scene.name : scene.name + "_" + std::to_string(output);
}

}  // namespace suffuse
