#include "suffuse/points.hpp"

#include "suffuse/error.hpp"

namespace suffuse {

int components_of(FieldKind kind, int dim) {
  switch (kind) {
    case FieldKind::Scalar: return 1;
    case FieldKind::Vector: return dim;
    case FieldKind::SymmetricTensor: return 6;
    case FieldKind::Tensor: return dim * dim;
  }
  return 1;
}

PointSet::PointSet(int dim) : dim_(dim) {
  using K = FieldKind;
  core_.position = add_field({"position", K::Vector, "m", "current position", false});
  core_.displacement = add_field({"displacement", K::Vector, "m", "displacement since the start", true});
  core_.velocity = add_field({"velocity", K::Vector, "m/s", "velocity", true});
  core_.mass = add_field({"mass", K::Scalar, "kg", "mass of the point (per metre of thickness in 2D)", true});
  core_.volume = add_field({"volume", K::Scalar, "m^3", "current volume (per metre of thickness in 2D: m^2)", true});
  core_.size = add_field({"size", K::Vector, "m", "edge lengths of the point's initial domain (GIMP)", false});
  core_.stress = add_field({"stress", K::SymmetricTensor, "Pa",
                            "Cauchy stress, tension positive (xx, yy, zz, yz, xz, xy)", true});
  core_.strain = add_field({"strain", K::SymmetricTensor, "-",
                            "small strain, tensor components (xx, yy, zz, yz, xz, xy)", true});
  core_.velocity_gradient =
      add_field({"velocity_gradient", K::Tensor, "1/s", "L_ij = dv_i/dx_j, row-major", false});
  core_.material_id = add_field({"material_id", K::Scalar, "-", "index of the material in the scene", true});
}

FieldId PointSet::add_field(const FieldInfo& info) {
  if (auto existing = find(info.name)) {
    if (fields_[*existing].info.kind != info.kind)
      throw Error("field '" + info.name + "' is registered twice with different kinds");
    return *existing;
  }
  const int k = components_of(info.kind, dim_);
  fields_.push_back(Field{info, k, std::vector<double>(size_ * k, 0.0)});
  // A 2D run is a slice of unit thickness: its masses and volumes are per
  // metre, and their outputs say so (docs/outputs.md, Units).
  std::string& unit = fields_.back().info.unit;
  if (dim_ == 2 && unit == "kg") unit = "kg/m";
  if (dim_ == 2 && unit == "m^3") unit = "m^2";
  return fields_.size() - 1;
}

std::optional<FieldId> PointSet::find(std::string_view name) const {
  for (std::size_t i = 0; i < fields_.size(); ++i)
    if (fields_[i].info.name == name) return i;
  return std::nullopt;
}

FieldId PointSet::id(std::string_view name) const {
  if (auto f = find(name)) return *f;
  throw Error("no point field named '" + std::string(name) + "'");
}

std::size_t PointSet::append(std::size_t count) {
  const std::size_t first = size_;
  size_ += count;
  for (Field& f : fields_) f.data.resize(size_ * f.components, 0.0);
  return first;
}

void PointSet::keep(std::size_t begin, std::size_t end) {
  if (begin > end || end > size_)
    throw Error("internal: keeping points [" + std::to_string(begin) + ", " + std::to_string(end) + ") of " +
                std::to_string(size_));
  for (Field& f : fields_) {
    const auto m = static_cast<std::size_t>(f.components);
    std::vector<double> kept(f.data.begin() + static_cast<std::ptrdiff_t>(begin * m),
                             f.data.begin() + static_cast<std::ptrdiff_t>(end * m));
    f.data.swap(kept);
  }
  size_ = end - begin;
}

}  // namespace suffuse
