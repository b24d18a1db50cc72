// writer/vtk_grid: the background grid as VTK image data (.vti) per frame,
// in the run's .pvd collection next to the points: the nodal fields the core
// projects (velocities of skeleton and liquid, pore pressure, Darcy flux,
// mass) as point data, and cell averages of point fields (porosity, fines
// content, concentration, eroded fraction, ...) and the point count per cell
// as cell data.
#include <algorithm>
#include <cmath>
#include <suffuse/error.hpp>
#include <suffuse/plugin.hpp>
#include <vector>

#include "vtk_files.hpp"

namespace {

namespace fs = std::filesystem;
using suffuse::FieldKind;

// Cell fields when the scene names none: those of erosion, if the run has them.
const std::vector<std::string> default_cell_fields = {"porosity", "fines_content", "concentration",
                                                      "eroded_fraction"};

class VtkGrid final : public suffuse::Writer {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.string_list("cell_fields").fallback(std::vector<std::string>{}).doc(
        "Point fields averaged over each cell (volume-weighted, over the points whose centre lies in it), "
        "scalars, vectors or symmetric tensors; empty: porosity, fines_content, concentration and eroded_fraction, "
        "those the run has. The point count of each cell is always written");
    s.boolean("compress").fallback(true).doc("Compress the appended binary data with zlib");
    return s;
  }
  // Fields named in the scene must exist in its run (checked at validation).
  static std::vector<std::string> required_fields(const suffuse::Parameters& p, int) {
    return p.string_list("cell_fields");
  }
  explicit VtkGrid(const suffuse::PluginArgs& args)
      : cell_fields_(args.params.string_list("cell_fields")), compress_(args.params.boolean("compress")) {}

  bool wants_grid_fields() const override { return true; }
  void open(const fs::path& directory, const std::string& basename) override {
    suffuse::vtk::load_module("writer/vtk_grid");
    files_.open(directory, basename + "_grid");
  }
  void resume(const fs::path& directory, const std::string& basename, const suffuse::ResumePoint& at) override {
    suffuse::vtk::load_module("writer/vtk_grid");
    files_.resume(directory, basename + "_grid", at);
  }

  void write(const suffuse::OutputFrame& frame) override {
    const suffuse::GridGeometry& g = frame.grid;
    const int dim = g.dim();
    suffuse::vtk::ImageFrame image;
    image.dim = dim;
    for (int a = 0; a < dim; ++a) {
      image.nodes[a] = g.nodes_per_axis()[a];
      image.origin[a] = g.origin()[a];
      image.spacing[a] = g.cell_size()[a];
    }
    for (const suffuse::GridField& f : frame.grid_fields) {
      const FieldKind kind = f.components == 1 ? FieldKind::Scalar : FieldKind::Vector;
      image.node_arrays.push_back({f.name, kind, g.node_count(), f.values.data(), f.unit});
    }
    std::vector<std::vector<double>> cell_values;  // the cell arrays' values, until written
    add_cell_averages(frame, image, cell_values);
    suffuse::vtk::write_image(image, files_.next_path(), compress_, "writer/vtk_grid");
    files_.written(frame.series, frame.time);
  }

 private:
  // Cell index of each point (its centre; on a face: the cell below it,
  // clamped to the grid).
  void locate(const suffuse::PointSet& pts, const suffuse::GridGeometry& g) {
    const int dim = g.dim();
    const double* x = pts.data(pts.core().position);
    cell_of_.resize(pts.size());
    for (std::size_t p = 0; p < pts.size(); ++p) {
      std::size_t cell = 0, stride = 1;
      for (int a = 0; a < dim; ++a) {
        const int i = static_cast<int>(std::floor((x[p * dim + a] - g.origin()[a]) / g.cell_size()[a]));
        cell += stride * static_cast<std::size_t>(std::clamp(i, 0, g.cells()[a] - 1));
        stride *= static_cast<std::size_t>(g.cells()[a]);
      }
      cell_of_[p] = cell;
    }
  }

  // Appends the point count and the averages of the cell fields to the
  // image's cell arrays, their values held in `values`.
  void add_cell_averages(const suffuse::OutputFrame& frame, suffuse::vtk::ImageFrame& image,
                         std::vector<std::vector<double>>& values) {
    const suffuse::PointSet& pts = frame.points;
    const suffuse::GridGeometry& g = frame.grid;
    const int dim = g.dim();
    std::size_t cells = 1;
    for (int a = 0; a < dim; ++a) cells *= static_cast<std::size_t>(g.cells()[a]);
    locate(pts, g);
    std::vector<std::string> names = cell_fields_;
    if (names.empty())
      for (const std::string& name : default_cell_fields)
        if (pts.find(name)) names.push_back(name);
    values.resize(names.size() + 1);
    const double* volume = pts.data(pts.core().volume);
    std::vector<double>& count = values[0];
    count.assign(cells, 0.0);
    std::vector<double> weight(cells, 0.0);
    for (std::size_t p = 0; p < pts.size(); ++p) {
      count[cell_of_[p]] += 1;
      weight[cell_of_[p]] += volume[p];
    }
    image.cell_arrays.push_back({"point_count", FieldKind::Scalar, cells, count.data(), "-"});
    for (std::size_t i = 0; i < names.size(); ++i) {
      const suffuse::FieldId f = pts.id(names[i]);
      const suffuse::FieldInfo& info = pts.info(f);
      if (info.kind == FieldKind::Tensor)
        throw suffuse::Error("writer/vtk_grid: cell field '" + names[i] +
                             "' is a full tensor; cell averages are of scalars, vectors and symmetric tensors");
      const int k = pts.components(f);
      const double* v = pts.data(f);
      std::vector<double>& mean = values[i + 1];
      mean.assign(cells * k, 0.0);
      for (std::size_t p = 0; p < pts.size(); ++p)
        for (int c = 0; c < k; ++c) mean[cell_of_[p] * k + c] += volume[p] * v[p * k + c];
      for (std::size_t c = 0; c < cells; ++c)
        for (int j = 0; j < k; ++j) mean[c * k + j] = weight[c] > 0 ? mean[c * k + j] / weight[c] : 0.0;
      image.cell_arrays.push_back({names[i], info.kind, cells, mean.data(), info.unit});
    }
  }

  std::vector<std::string> cell_fields_;
  bool compress_;
  suffuse::vtk::FrameFiles files_{"vti"};
  std::vector<std::size_t> cell_of_;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::Writer, VtkGrid>(
      "writer/vtk_grid",
      "The grid as VTK image data (.vti) per frame, in the run's .pvd next to the points: nodal velocities, pore "
      "pressure, Darcy flux, and cell averages of porosity, fines content, concentration, eroded fraction");
}
