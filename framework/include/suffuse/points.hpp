#pragma once
// Material points, stored as structure-of-arrays: one contiguous array per
// named field. A field of k components holds k values per point, interleaved
// (point p, component c at index p*k + c), so a point's vector or tensor is a
// small contiguous block and each field is one array a kernel can stream.
//
// Plugins add their own fields (for example "porosity") through add_field();
// writers output every field flagged `output`. Look fields up by name once, at
// set-up, and keep the FieldId.
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace suffuse {

using FieldId = std::size_t;

// Symmetric tensors use 6 Voigt components in 2D and 3D alike
// (xx, yy, zz, yz, xz, xy), so plane strain keeps sigma_zz.
enum class FieldKind {
  Scalar,           // 1 component
  Vector,           // dim components
  SymmetricTensor,  // 6 components
  Tensor            // dim*dim components, row-major
};

struct FieldInfo {
  std::string name;
  FieldKind kind = FieldKind::Scalar;
  std::string unit;  // SI, "-" dimensionless; in 2D the point set gives "kg" as "kg/m", "m^3" as "m^2"
  std::string description;
  bool output = true;  // written by writers
};

int components_of(FieldKind kind, int dim);

class PointSet {
 public:
  explicit PointSet(int dim);

  int dim() const { return dim_; }
  std::size_t size() const { return size_; }

  // Adds a field, or returns the existing one if a field of that name and kind
  // exists already. Throws suffuse::Error if the name exists with another kind.
  FieldId add_field(const FieldInfo& info);
  std::optional<FieldId> find(std::string_view name) const;
  FieldId id(std::string_view name) const;  // throws if absent
  std::size_t field_count() const { return fields_.size(); }
  const FieldInfo& info(FieldId id) const { return fields_[id].info; }
  int components(FieldId id) const { return fields_[id].components; }

  std::span<double> values(FieldId id) { return fields_[id].data; }
  std::span<const double> values(FieldId id) const { return fields_[id].data; }
  double* data(FieldId id) { return fields_[id].data.data(); }
  const double* data(FieldId id) const { return fields_[id].data.data(); }

  // Grows every field; new values are zero. Returns the index of the first new point.
  std::size_t append(std::size_t count);
  // Keeps the points [begin, end) only, renumbered from 0 (a process's share
  // of a run on many processes), and frees the rest.
  void keep(std::size_t begin, std::size_t end);

  // Ids of the fields every simulation has.
  struct CoreFields {
    FieldId position, displacement, velocity, mass, volume, size, stress, strain,
        velocity_gradient, material_id;
  };
  const CoreFields& core() const { return core_; }

 private:
  struct Field {
    FieldInfo info;
    int components;
    std::vector<double> data;
  };
  int dim_;
  std::size_t size_ = 0;
  std::vector<Field> fields_;
  CoreFields core_{};
};

}  // namespace suffuse
