// writer/vtk_grid: the background grid as VTK image data (.vti) per frame,
// in the run's .pvd collection next to the points: the nodal fields the core
// projects (velocities of skeleton and liquid, pore pressure, Darcy flux,
// mass) as point data, and cell averages of point fields (porosity, fines
// content, concentration, eroded fraction, ...) and the point count per cell
// as cell data.
#include <vtkCellData.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkXMLImageDataWriter.h>

#include <algorithm>
#include <cmath>
#include <suffuse/error.hpp>
#include <suffuse/plugin.hpp>
#include <vector>

#include "vtk_common.hpp"

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
    files_.open(directory, basename + "_grid");
  }
  void resume(const fs::path& directory, const std::string& basename, const suffuse::ResumePoint& at) override {
    files_.resume(directory, basename + "_grid", at);
  }

  void write(const suffuse::OutputFrame& frame) override {
    const suffuse::GridGeometry& g = frame.grid;
    const int dim = g.dim();
    vtkNew<vtkImageData> image;
    const auto& nodes = g.nodes_per_axis();
    image->SetDimensions(nodes[0], nodes[1], dim == 3 ? nodes[2] : 1);
    image->SetOrigin(g.origin()[0], g.origin()[1], dim == 3 ? g.origin()[2] : 0.0);
    image->SetSpacing(g.cell_size()[0], g.cell_size()[1], dim == 3 ? g.cell_size()[2] : 1.0);
    for (const suffuse::GridField& f : frame.grid_fields) {
      const FieldKind kind = f.components == 1 ? FieldKind::Scalar : FieldKind::Vector;
      image->GetPointData()->AddArray(suffuse::vtk::make_array(f.name, kind, dim, g.node_count(), f.values.data()));
    }
    add_cell_averages(frame, *image);
    vtkNew<vtkXMLImageDataWriter> writer;
    writer->SetInputData(image);
    suffuse::vtk::write_atomically(*writer, files_.next_path(), compress_, "writer/vtk_grid");
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

  void add_cell_averages(const suffuse::OutputFrame& frame, vtkImageData& image) {
    const suffuse::PointSet& pts = frame.points;
    const suffuse::GridGeometry& g = frame.grid;
    const int dim = g.dim();
    std::size_t cells = 1;
    for (int a = 0; a < dim; ++a) cells *= static_cast<std::size_t>(g.cells()[a]);
    locate(pts, g);
    const double* volume = pts.data(pts.core().volume);
    std::vector<double> count(cells, 0.0), weight(cells, 0.0);
    for (std::size_t p = 0; p < pts.size(); ++p) {
      count[cell_of_[p]] += 1;
      weight[cell_of_[p]] += volume[p];
    }
    image.GetCellData()->AddArray(suffuse::vtk::make_array("point_count", FieldKind::Scalar, dim, cells, count.data()));
    std::vector<std::string> names = cell_fields_;
    if (names.empty())
      for (const std::string& name : default_cell_fields)
        if (pts.find(name)) names.push_back(name);
    std::vector<double> mean;
    for (const std::string& name : names) {
      const suffuse::FieldId f = pts.id(name);
      const suffuse::FieldInfo& info = pts.info(f);
      if (info.kind == FieldKind::Tensor)
        throw suffuse::Error("writer/vtk_grid: cell field '" + name +
                             "' is a full tensor; cell averages are of scalars, vectors and symmetric tensors");
      const int k = pts.components(f);
      const double* v = pts.data(f);
      mean.assign(cells * k, 0.0);
      for (std::size_t p = 0; p < pts.size(); ++p)
        for (int c = 0; c < k; ++c) mean[cell_of_[p] * k + c] += volume[p] * v[p * k + c];
      for (std::size_t c = 0; c < cells; ++c)
        for (int i = 0; i < k; ++i) mean[c * k + i] = weight[c] > 0 ? mean[c * k + i] / weight[c] : 0.0;
      image.GetCellData()->AddArray(suffuse::vtk::make_array(name, info.kind, dim, cells, mean.data()));
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
