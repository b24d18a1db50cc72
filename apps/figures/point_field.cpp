// One field of a frame's material points (see point_field.hpp).
#include "point_field.hpp"

#include <vtkDataArray.h>
#include <vtkInformation.h>
#include <vtkPointData.h>

#include <cmath>
#include <suffuse/error.hpp>

namespace suffuse::plot {

namespace {

// The names a user may give a component of ARRAY.
std::vector<std::string> component_names(vtkDataArray* array) {
  const int n = array->GetNumberOfComponents();
  std::vector<std::string> names;
  for (int c = 0; c < n; ++c) {
    const char* given = array->GetComponentName(c);
    names.push_back(given ? given : n == 3 ? std::string(1, static_cast<char>('x' + c)) : std::to_string(c));
  }
  return names;
}

std::string available_fields(vtkPointData* data) {
  std::string list;
  for (int a = 0; a < data->GetNumberOfArrays(); ++a) {
    vtkDataArray* array = data->GetArray(a);
    if (!array || !array->GetName()) continue;
    std::string entry = array->GetName();
    if (array->GetNumberOfComponents() > 1) {
      entry += " (";
      for (const auto& c : component_names(array)) entry += entry.back() == '(' ? ":" + c : ", :" + c;
      entry += array->GetNumberOfComponents() == 3 ? ", :magnitude)" : ")";
    }
    list += (list.empty() ? "" : ", ") + entry;
  }
  return list;
}

}  // namespace

PointField point_field(vtkPolyData* points, const std::string& spec) {
  const auto colon = spec.find(':');
  const std::string name = spec.substr(0, colon);
  const std::string component = colon == std::string::npos ? "" : spec.substr(colon + 1);
  vtkPointData* data = points->GetPointData();
  vtkDataArray* array = name.empty() ? nullptr : data->GetArray(name.c_str());
  if (!array) throw Error("no field '" + name + "'; the fields are: " + available_fields(data));

  const int n = array->GetNumberOfComponents();
  // -1: the magnitude, of a vector only (a tensor's would depend on how its
  // components are stored).
  int which = n == 1 ? 0 : -1;
  if (n == 1 && !component.empty())
    throw Error("field '" + name + "' is a scalar: it has no component '" + component + "'");
  if (n != 1 && n != 3 && (component.empty() || component == "magnitude")) {
    std::string list;
    for (const auto& c : component_names(array)) list += (list.empty() ? "" : ", ") + name + ":" + c;
    throw Error("field '" + name + "' has " + std::to_string(n) + " components: name one (" + list + ")");
  }
  if (n > 1 && !component.empty() && component != "magnitude") {
    const auto names = component_names(array);
    which = -2;
    for (int c = 0; c < n; ++c)
      if (names[c] == component || std::to_string(c) == component) which = c;
    if (which == -2) {
      std::string list;
      for (const auto& c : names) list += c + ", ";
      throw Error("field '" + name + "' has no component '" + component + "'; expected one of " +
                  (n == 3 ? list + "magnitude" : list.substr(0, list.size() - 2)));
    }
  }

  PointField field;
  field.name = spec;
  field.label = name + (which >= 0 && n > 1 ? " " + component_names(array)[which]
                        : n > 1             ? " magnitude"
                                            : "");
  vtkInformation* info = array->GetInformation();
  if (info && info->Has(vtkDataArray::UNITS_LABEL())) field.label += std::string(" [") + info->Get(vtkDataArray::UNITS_LABEL()) + "]";
  const vtkIdType count = points->GetNumberOfPoints();
  if (array->GetNumberOfTuples() != count)
    throw Error("field '" + name + "' has " + std::to_string(array->GetNumberOfTuples()) + " values for " +
                std::to_string(count) + " points");
  field.values.resize(static_cast<std::size_t>(count));
  for (vtkIdType p = 0; p < count; ++p) {
    double v = 0;
    if (which >= 0) v = array->GetComponent(p, which);
    else {
      for (int c = 0; c < n; ++c) v += array->GetComponent(p, c) * array->GetComponent(p, c);
      v = std::sqrt(v);
    }
    field.values[static_cast<std::size_t>(p)] = v;
  }
  return field;
}

bool is_planar(vtkPolyData* points) {
  double bounds[6];
  points->GetBounds(bounds);
  return bounds[4] == 0 && bounds[5] == 0;
}

std::vector<std::array<double, 3>> point_sizes(vtkPolyData* points) {
  const vtkIdType count = points->GetNumberOfPoints();
  std::vector<std::array<double, 3>> sizes(static_cast<std::size_t>(count));
  vtkPointData* data = points->GetPointData();
  if (vtkDataArray* size = data->GetArray("size"); size && size->GetNumberOfComponents() == 3) {
    for (vtkIdType p = 0; p < count; ++p) size->GetTuple(p, sizes[static_cast<std::size_t>(p)].data());
    return sizes;
  }
  vtkDataArray* volume = data->GetArray("volume");
  if (!volume || volume->GetNumberOfComponents() != 1)
    throw Error("the points have neither a 'size' nor a 'volume' field: their boxes are unknown");
  const bool planar = is_planar(points);
  for (vtkIdType p = 0; p < count; ++p) {
    // In 2D the volume is per metre of thickness: an area.
    const double v = std::max(0.0, volume->GetComponent(p, 0));
    const double edge = planar ? std::sqrt(v) : std::cbrt(v);
    sizes[static_cast<std::size_t>(p)] = {edge, edge, planar ? 0.0 : edge};
  }
  return sizes;
}

}  // namespace suffuse::plot
