#pragma once
// Which per-point fields a scene's run provides, known before anything is
// built, so that a plugin reading a field nobody provides is refused at
// validation with the field's name.
#include <string>
#include <vector>

#include "suffuse/plugin.hpp"
#include "suffuse/scene.hpp"

namespace suffuse::detail {

// A point field a part registers, and the member of the part's id struct
// that keeps its id: one list per part gives both the registration and the
// names validation checks against.
template <class Ids>
struct FieldDeclaration {
  FieldInfo info;
  FieldId Ids::*id;
};

template <class Ids>
Ids register_fields(PointSet& points, const std::vector<FieldDeclaration<Ids>>& declarations) {
  Ids ids{};
  for (const auto& d : declarations) ids.*d.id = points.add_field(d.info);
  return ids;
}

struct ProvidedField {
  std::string name;
  std::string owner;  // the part that provides it, and when
  bool provided;      // in this scene
};

// Every field a part of the core can provide, with whether this scene's run has it.
std::vector<ProvidedField> point_fields_of(const Scene& scene, const Registry& registry);

}  // namespace suffuse::detail
