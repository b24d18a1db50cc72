// The surface module (surface.hpp): VTK's readers, its closedness check and
// its inside test, behind the entries the core calls through
// PluginLoader::load_module (a surface's seeds; a .vtp file's points).
#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkFeatureEdges.h>
#include <vtkNew.h>
#include <vtkOBBTree.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyDataNormals.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>
#include <vtkSelectEnclosedPoints.h>
#include <vtkSmartPointer.h>
#include <vtkTriangleFilter.h>
#include <vtkXMLPolyDataReader.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "geometry/surface.hpp"
#include "suffuse/error.hpp"
#include "suffuse/version.hpp"

namespace {

using suffuse::Error;
namespace fs = std::filesystem;

std::string text(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}

// The file's triangles: STL (coincident vertices merged, as a closed
// surface needs) or VTK XML polygonal data (.vtp), polygons triangulated.
vtkSmartPointer<vtkPolyData> read_triangles(const fs::path& file) {
  if (!fs::is_regular_file(file)) throw Error(file.string() + ": no such file");
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  vtkSmartPointer<vtkPolyData> data;
  if (ext == ".stl") {
    vtkNew<vtkSTLReader> reader;
    reader->SetFileName(file.c_str());
    reader->MergingOn();
    reader->Update();
    data = reader->GetOutput();
  } else if (ext == ".vtp") {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName(file.c_str());
    reader->Update();
    data = reader->GetOutput();
  } else {
    throw Error(file.string() + ": not a surface file: expected .stl or .vtp, found \"" + ext + "\"");
  }
  if (!data || data->GetNumberOfPolys() == 0)
    throw Error(file.string() + ": no surface: expected triangles (or polygons), found none");
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputData(data);
  triangles->PassVertsOff();
  triangles->PassLinesOff();
  // Triangles turned consistently, outward: the tree's crossings alternate
  // entering and leaving by the triangles' sense (STL files often hold some
  // turned the other way).
  vtkNew<vtkPolyDataNormals> oriented;
  oriented->SetInputConnection(triangles->GetOutputPort());
  oriented->ConsistencyOn();
  oriented->AutoOrientNormalsOn();
  oriented->SplittingOff();
  oriented->ComputePointNormalsOff();
  oriented->ComputeCellNormalsOff();
  oriented->Update();
  vtkSmartPointer<vtkPolyData> out = oriented->GetOutput();
  return out;
}

// Edges bounding one triangle (a hole) or more than two (a fin): an inside
// test means nothing across them.
vtkIdType open_edges(vtkPolyData* surface) {
  vtkNew<vtkFeatureEdges> edges;
  edges->SetInputData(surface);
  edges->BoundaryEdgesOn();
  edges->NonManifoldEdgesOn();
  edges->FeatureEdgesOff();
  edges->ManifoldEdgesOff();
  edges->Update();
  return edges->GetOutput()->GetNumberOfLines();
}

}  // namespace

extern "C" void suffuse_surface_seed(const fs::path& file, const suffuse::detail::SurfaceLattice& lattice,
                                     suffuse::detail::SurfaceSeeds& seeds) {
  vtkSmartPointer<vtkPolyData> surface = read_triangles(file);
  seeds.triangles = static_cast<std::size_t>(surface->GetNumberOfPolys());
  if (const vtkIdType open = open_edges(surface); open > 0)
    throw Error(file.string() + ": open surface: expected a closed surface (every edge shared by two triangles), "
                "found " + std::to_string(open) + " edges bounding one triangle or more than two");
  double b[6];
  surface->GetBounds(b);
  for (int a = 0; a < 3; ++a) {
    seeds.min[a] = b[2 * a], seeds.max[a] = b[2 * a + 1];
    const double lo = lattice.origin[a], hi = lo + lattice.cell_size[a] * lattice.cells[a];
    if (!(b[2 * a] >= lo && b[2 * a + 1] <= hi))
      throw Error(file.string() + ": surface outside the grid: expected " + std::string(1, char('x' + a)) +
                  " within [" + text(lo) + ", " + text(hi) + "], found [" + text(b[2 * a]) + ", " +
                  text(b[2 * a + 1]) + "]");
  }
  // The lattice points within the surface's bounds: index ranges per axis.
  std::array<double, 3> spacing{};
  std::array<long, 3> first{}, last{};
  for (int a = 0; a < 3; ++a) {
    spacing[a] = lattice.cell_size[a] / lattice.per_cell;
    const long count = static_cast<long>(lattice.cells[a]) * lattice.per_cell;
    first[a] = std::clamp(static_cast<long>(std::floor((b[2 * a] - lattice.origin[a]) / spacing[a] - 0.5)), 0L, count - 1);
    last[a] = std::clamp(static_cast<long>(std::ceil((b[2 * a + 1] - lattice.origin[a]) / spacing[a] - 0.5)), 0L, count - 1);
  }
  const double volume = spacing[0] * spacing[1] * spacing[2];
  // Row by row along x: the row's line crossed with the surface once
  // (vtkOBBTree, whose crossings alternate entering and leaving), its points
  // inside between an entry and the next exit; a row whose crossings do not
  // pair up (through a vertex or along an edge) asks vtkSelectEnclosedPoints
  // point by point. A test per point took 30 s for 1.2 million points.
  vtkNew<vtkOBBTree> tree;
  tree->SetDataSet(surface);
  tree->SetTolerance(1e-9 * spacing[0]);  // absolute (1e-3 by default): far below the lattice
  tree->BuildLocator();
  vtkNew<vtkSelectEnclosedPoints> inside;
  inside->Initialize(surface);
  vtkNew<vtkPoints> crossings;
  const double margin = spacing[0] + 1e-6 * (b[1] - b[0]);
  std::vector<double> at;
  for (long k = first[2]; k <= last[2]; ++k)
    for (long j = first[1]; j <= last[1]; ++j) {
      const double y = lattice.origin[1] + (j + 0.5) * spacing[1], z = lattice.origin[2] + (k + 0.5) * spacing[2];
      const double from[3] = {b[0] - margin, y, z}, to[3] = {b[1] + margin, y, z};
      crossings->Reset();
      tree->IntersectWithLine(from, to, crossings, nullptr);
      at.clear();
      for (vtkIdType c = 0; c < crossings->GetNumberOfPoints(); ++c) at.push_back(crossings->GetPoint(c)[0]);
      std::sort(at.begin(), at.end());
      const bool paired = at.size() % 2 == 0;
      for (long i = first[0]; i <= last[0]; ++i) {
        double x[3] = {lattice.origin[0] + (i + 0.5) * spacing[0], y, z};
        const bool in = paired ? (std::upper_bound(at.begin(), at.end(), x[0]) - at.begin()) % 2 == 1
                               : inside->IsInsideSurface(x) != 0;
        if (in) seeds.points.insert(seeds.points.end(), {x[0], x[1], x[2], volume});
      }
    }
  inside->Complete();
  if (seeds.points.empty())
    throw Error(file.string() + ": no point inside: expected a surface holding at least one point of the lattice (" +
                text(spacing[0]) + " m apart), found none");
}

// A body's points from VTK XML polygonal data: the file's points (z zero
// in 2D), its point-data array "volume", one component, and the arrays of
// initial fields it holds (surface.hpp).
extern "C" void suffuse_points_read(const fs::path& file, int dim, suffuse::detail::VtpPoints& points) {
  if (!fs::is_regular_file(file)) throw Error(file.string() + ": no such file");
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkPolyData* data = reader->GetOutput();
  const vtkIdType n = data ? data->GetNumberOfPoints() : 0;
  if (n == 0) throw Error(file.string() + ": no point: expected VTK XML polygonal data with points, found none");
  vtkDataArray* volume = data->GetPointData()->GetArray("volume");
  if (!volume || volume->GetNumberOfComponents() != 1)
    throw Error(file.string() + ": no volumes: expected a point-data array \"volume\" of one component (m^" +
                std::to_string(dim) + ")" + (volume ? ", found one of " + std::to_string(volume->GetNumberOfComponents())
                                                    : ", found none"));
  std::vector<double>& rows = points.rows;
  rows.clear();
  rows.reserve(static_cast<std::size_t>(n) * static_cast<std::size_t>(dim + 1));
  for (vtkIdType k = 0; k < n; ++k) {
    const double* x = data->GetPoint(k);
    if (dim == 2 && x[2] != 0)
      throw Error(file.string() + ": point " + std::to_string(k) + " out of the plane: expected z = 0 in 2D, found " +
                  text(x[2]));
    for (int a = 0; a < dim; ++a) rows.push_back(x[a]);
    rows.push_back(volume->GetTuple1(k));
  }
  // The initial fields, as vtk_particles writes them: a symmetric tensor in
  // VTK's order XX YY ZZ XY YZ XZ, a vector with three components.
  struct Wanted {
    const char* name;
    int components;
  };
  points.fields.clear();
  for (const Wanted w : {Wanted{"stress", 6}, Wanted{"pore_pressure", 1}, Wanted{"porosity", 1},
                         Wanted{"velocity", 3}, Wanted{"fines_content", 1}, Wanted{"liquid_velocity", 3},
                         Wanted{"saturation", 1}}) {
    vtkDataArray* array = data->GetPointData()->GetArray(w.name);
    if (!array) continue;
    if (array->GetNumberOfComponents() != w.components)
      throw Error(file.string() + ": array \"" + w.name + "\" with " + std::to_string(array->GetNumberOfComponents()) +
                  " components: expected " + std::to_string(w.components) + ", as suffuse writes it");
    std::vector<double> values;
    const int kept = w.components == 3 ? dim : w.components;
    values.reserve(static_cast<std::size_t>(n) * static_cast<std::size_t>(kept));
    double t[6];
    for (vtkIdType k = 0; k < n; ++k) {
      array->GetTuple(k, t);
      if (w.components == 6) {
        for (const int c : {0, 1, 2, 4, 5, 3}) values.push_back(t[c]);  // xx yy zz yz xz xy
      } else {
        for (int c = 0; c < kept; ++c) values.push_back(t[c]);
      }
    }
    points.fields.emplace_back(w.name, std::move(values));
  }
}

extern "C" const char* suffuse_surface_module_version() { return suffuse::framework_version; }

static_assert(std::is_same_v<decltype(suffuse_surface_seed), suffuse::detail::SeedSurfaceEntry>);
static_assert(std::is_same_v<decltype(suffuse_points_read), suffuse::detail::ReadPointsEntry>);
