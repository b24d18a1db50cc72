#pragma once
// A body's initial value of a field at one of its points: the value its
// points file gives that point (BodySpec::point_values), else the body's
// key. `rows`: the file's row of each of the body's points (points an
// earlier body holds were dropped); empty for bodies of a shape.
#include <cstddef>
#include <optional>
#include <span>

#include "mpm/domain.hpp"
#include "suffuse/scene.hpp"

namespace suffuse::detail {

class InitialValues {
 public:
  InitialValues(const BodySpec& body, const BodyPoints& points, std::span<const std::size_t> rows, int dim)
      : body_(body), first_(points.range.begin), rows_(rows), dim_(static_cast<std::size_t>(dim)) {}

  double porosity(std::size_t p) const { return one(body_.point_values.porosity, p, body_.porosity); }
  double pore_pressure(std::size_t p) const { return one(body_.point_values.pore_pressure, p, body_.pore_pressure); }
  double fines_content(std::size_t p) const { return one(body_.point_values.fines_content, p, body_.fines_content); }
  double stress(std::size_t p, int c) const {
    const auto& v = body_.point_values.stress;
    return v.empty() ? body_.stress[static_cast<std::size_t>(c)] : v[row(p) * 6 + static_cast<std::size_t>(c)];
  }
  double velocity(std::size_t p, int a) const {
    const auto& v = body_.point_values.velocity;
    return v.empty() ? body_.velocity[static_cast<std::size_t>(a)] : v[row(p) * dim_ + static_cast<std::size_t>(a)];
  }
  double liquid_velocity(std::size_t p, int a) const {
    const auto& v = body_.point_values.liquid_velocity;
    return v.empty() ? velocity(p, a) : v[row(p) * dim_ + static_cast<std::size_t>(a)];
  }
  // The file's saturation of the point, if it gives one.
  std::optional<double> saturation(std::size_t p) const {
    const auto& v = body_.point_values.saturation;
    return v.empty() ? std::nullopt : std::optional<double>(v[row(p)]);
  }

 private:
  std::size_t row(std::size_t p) const { return rows_[p - first_]; }
  double one(const std::vector<double>& v, std::size_t p, double key) const { return v.empty() ? key : v[row(p)]; }

  const BodySpec& body_;
  std::size_t first_;
  std::span<const std::size_t> rows_;
  std::size_t dim_;
};

}  // namespace suffuse::detail
