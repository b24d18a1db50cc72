#pragma once
// Bodies inside closed triangulated surfaces (3D: STL or VTK .vtp files;
// docs/geometry.md), and bodies of points from .vtp files. VTK reads the file, checks that it is closed and tells
// which points of the grid's lattice are inside (vtkSelectEnclosedPoints),
// in a module loaded when a scene has such a body (surface_module.cpp): the
// core itself never maps VTK's libraries.
#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace suffuse::detail {

// The lattice of a body's points: `per_cell` points per cell and axis of the
// grid from `origin`, cells of `cell_size`, `cells` of them per axis.
struct SurfaceLattice {
  std::array<double, 3> origin{}, cell_size{};
  std::array<int, 3> cells{};
  int per_cell = 2;
};

// What a surface seeds: a row (x, y, z, volume) per lattice point whose
// centre is inside, and the surface's bounds and triangle count.
struct SurfaceSeeds {
  std::vector<double> points;
  std::array<double, 3> min{}, max{};
  std::size_t triangles = 0;
};

// Throws suffuse::Error naming the file: unreadable, not a surface of
// triangles, open (edges bounding one triangle, or more than two), outside
// the grid, or holding no lattice point.
SurfaceSeeds seed_surface(const std::filesystem::path& file, const SurfaceLattice& lattice);

// A body's points from a VTK XML polygonal data file (.vtp): a row (the dim
// coordinates, the volume) per point, from its points and its point-data
// array "volume"; and the initial fields the file holds, of the arrays
// "stress" (6 components; returned in suffuse's order xx yy zz yz xz xy),
// "pore_pressure", "porosity", "velocity" and "liquid_velocity" (3
// components; returned with dim), "fines_content" and "saturation", as a
// suffuse run writes them. Throws suffuse::Error
// naming the file: unreadable, no point, no volumes, one of those arrays
// with other components, or (2D) a point off the plane z = 0.
struct VtpPoints {
  std::vector<double> rows;
  std::vector<std::pair<std::string, std::vector<double>>> fields;  // name, values per point
};
VtpPoints read_vtp_points(const std::filesystem::path& file, int dim);

// The module's entries (surface_module.cpp).
using SeedSurfaceEntry = void(const std::filesystem::path& file, const SurfaceLattice& lattice, SurfaceSeeds& seeds);
using ReadPointsEntry = void(const std::filesystem::path& file, int dim, VtpPoints& points);

}  // namespace suffuse::detail
