#pragma once
// The point fields a part of the core registers, declared once (see
// scene/provided_fields.hpp for the names validation checks against).
#include <string>
#include <vector>

#include "suffuse/plugin.hpp"

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

}  // namespace suffuse::detail
