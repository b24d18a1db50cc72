// Outputs: writer plugin nodes, with the interval the core reads from each.
#include "scene_reader.hpp"

namespace suffuse::detail {

namespace {

ParameterSchema output_schema() {
  ParameterSchema s;
  s.number("interval").with_unit("s").above(0).may_be_absent().doc(
      "Simulation time between frames; absent: end time / 20. The initial and final states are always written");
  
  return s;
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
    }
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
