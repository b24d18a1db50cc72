#pragma once
// Which per-point fields a scene's run provides, known before anything is
// built, so that a plugin reading a field nobody provides is refused at
// validation with the field's name.
#include <string>
#include <vector>

#include "suffuse/plugin.hpp"
#include "suffuse/scene.hpp"

namespace suffuse::detail {

struct ProvidedField {
  std::string name;
  std::string owner;  // the part that provides it, and when
  bool provided;      // in this scene
};

// Every field a part of the core can provide, with whether this scene's run has it.
std::vector<ProvidedField> point_fields_of(const Scene& scene, const Registry& registry);

}  // namespace suffuse::detail
