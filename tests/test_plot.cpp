// suffuse plot: line charts of CSV columns drawn offscreen (no display) and
// written as PNG; read back with VTK's PNG reader. Then the figures of a run's
// point series (profile, map, animate) from a small synthetic run.
#include <gif_lib.h>
#include <gtest/gtest.h>
#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataWriter.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <string>
#include <suffuse/error.hpp>

#include "animation.hpp"
#include "test_support.hpp"
#include "colour_map.hpp"
#include "field_profile.hpp"
#include "point_field.hpp"
#include "vtk_series.hpp"

namespace {

namespace fs = std::filesystem;
using suffuse::test::fresh_dir;

void write(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

using suffuse::test::slurp;

// Runs suffuse plot ARGS in DIR; its exit status, with stdout and stderr in DIR/log.txt.
int plot(const fs::path& dir, const std::string& args) {
  const std::string command = "cd " + dir.string() + " && " + std::string(SUFFUSE_EXECUTABLE) + " plot " + args +
                              " > log.txt 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

const char* growth =
    "time [s],height [m],width [m]\n"
    "0,0,1\n"
    "1,0.5,1.5\n"
    "2,2,1.2\n"
    "3,4.5,2.5\n";

const char* decay =
    "time [s],height [m],width [m]\n"
    "0,5,0\n"
    "1,2.5,0.5\n"
    "2,1.25,0.25\n"
    "3,0.6,1\n";

TEST(Plot, WritesAPngOfTheRequestedSize) {
  const fs::path dir = fresh_dir("plot_png");
  write(dir / "run.growth.csv", growth);
  write(dir / "run.decay.csv", decay);
  ASSERT_EQ(plot(dir, "--png chart.png --x time --y height --y 'width [m]' --title 'Two runs' --width 640 "
                      "--height 480 --scale-y 100 run.growth.csv run.decay.csv"),
            0)
      << slurp(dir / "log.txt");
  EXPECT_EQ(slurp(dir / "log.txt"), "");  // nothing from VTK on the terminal
  ASSERT_TRUE(fs::exists(dir / "chart.png"));
  EXPECT_FALSE(fs::exists(dir / "chart.png.part"));

  vtkNew<vtkPNGReader> reader;
  ASSERT_TRUE(reader->CanReadFile((dir / "chart.png").c_str()));
  reader->SetFileName((dir / "chart.png").c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  EXPECT_EQ(dims[0], 640);
  EXPECT_EQ(dims[1], 480);
  vtkDataArray* pixels = image->GetPointData()->GetScalars();
  ASSERT_NE(pixels, nullptr);
  ASSERT_GE(pixels->GetNumberOfComponents(), 3);
  // A white background with black text and four coloured lines: many colours.
  std::set<std::array<int, 3>> colours;
  for (vtkIdType p = 0; p < pixels->GetNumberOfTuples(); ++p)
    colours.insert({static_cast<int>(pixels->GetComponent(p, 0)), static_cast<int>(pixels->GetComponent(p, 1)),
                    static_cast<int>(pixels->GetComponent(p, 2))});
  EXPECT_GT(colours.size(), 10u);
  EXPECT_TRUE(colours.count({255, 255, 255}));
  EXPECT_TRUE(colours.count({0, 0, 0}));
}

TEST(Plot, UnknownColumnNamesTheAvailableOnes) {
  const fs::path dir = fresh_dir("plot_column");
  write(dir / "growth.csv", growth);
  EXPECT_EQ(plot(dir, "--png chart.png --x time --y depth growth.csv"), 1);
  const std::string log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("no column 'depth'"), std::string::npos) << log;
  for (const char* column : {"'time [s]'", "'height [m]'", "'width [m]'"})
    EXPECT_NE(log.find(column), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir / "chart.png"));
  EXPECT_FALSE(fs::exists(dir / "chart.png.part"));
}

TEST(Plot, MissingFileFails) {
  const fs::path dir = fresh_dir("plot_missing");
  write(dir / "growth.csv", growth);
  EXPECT_EQ(plot(dir, "--png chart.png --x time --y height growth.csv absent.csv"), 1);
  const std::string log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("absent.csv"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir / "chart.png"));
}

TEST(Plot, BadCellsAndEmptyFilesFail) {
  const fs::path dir = fresh_dir("plot_bad");
  write(dir / "text.csv", "time [s],height [m]\n0,1\n1,tall\n");
  EXPECT_EQ(plot(dir, "--png chart.png --x time --y height text.csv"), 1);
  std::string log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("line 3, column 'height [m]': 'tall' is not a number"), std::string::npos) << log;

  write(dir / "empty.csv", "");
  EXPECT_EQ(plot(dir, "--png chart.png --x time --y height empty.csv"), 1);
  log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("empty.csv is empty"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir / "chart.png"));
}

}  // namespace

// ---------------------------------------------------------------- figures of a run's point series

namespace {

namespace series_fixture {

// A 2D run in a .pvd: 4 x 10 points of 0.1 m boxes over [0, 0.4] x [0, 1] at
// t = 0, 1 and 2.5 s, with porosity = 0.3 + 0.1 y + 0.01 t, velocity (3, 4, 0)
// and volume 0.01 (a 0.1 m square in 2D); the collection also lists a grid
// part, which the reader must skip. With LAYERS, a 3D run of that many layers
// of 0.1 m cubes in z, porosity + 0.2 z.
double porosity(double y, double t, double z = 0) { return 0.3 + 0.1 * y + 0.01 * t + 0.2 * z; }
const double times[] = {0, 1, 2.5};

void write_frame(const fs::path& file, double t, int layers) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();  // as suffuse writes them
  vtkNew<vtkCellArray> vertices;
  vtkNew<vtkDoubleArray> phi, velocity, volume, stress;
  phi->SetName("porosity");
  phi->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "-");
  velocity->SetName("velocity");
  velocity->SetNumberOfComponents(3);
  volume->SetName("volume");
  stress->SetName("stress");  // as writer/vtk_particles names a symmetric tensor's components
  stress->SetNumberOfComponents(6);
  const char* components[] = {"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
  for (int c = 0; c < 6; ++c) stress->SetComponentName(c, components[c]);
  for (int k = 0; k < std::max(1, layers); ++k)
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 10; ++j) {
        const double x = 0.05 + 0.1 * i, y = 0.05 + 0.1 * j, z = layers ? 0.05 + 0.1 * k : 0;
        const vtkIdType id = points->InsertNextPoint(x, y, z);
        vertices->InsertNextCell(1, &id);
        phi->InsertNextValue(porosity(y, t, z));
        velocity->InsertNextTuple3(3, 4, 0);
        volume->InsertNextValue(layers ? 0.001 : 0.01);
        stress->InsertNextTuple6(-1, -2, -3, 0.5, 0, 0);
      }
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(points);
  poly->SetVerts(vertices);
  for (vtkDoubleArray* a : {phi.Get(), velocity.Get(), volume.Get(), stress.Get()}) poly->GetPointData()->AddArray(a);
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetFileName(file.c_str());
  writer->SetInputData(poly);
  ASSERT_EQ(writer->Write(), 1);
}

// The run in DIR/run (run.pvd and its frames); the path of the directory.
fs::path write_run(const fs::path& dir, int layers = 0) {
  const fs::path run = dir / "run";
  fs::create_directories(run);
  std::string pvd = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
  // Listed out of order, with a grid part: the reader sorts and skips.
  for (int k : {2, 0, 1}) {
    const std::string name = "run_00000" + std::to_string(k) + ".vtp";
    write_frame(run / name, times[k], layers);
    // The grid first, as part 0, like a scene that lists writer/vtk_grid before writer/vtk_particles.
    pvd += "    <DataSet timestep=\"" + std::to_string(times[k]) + "\" group=\"\" part=\"0\" file=\"grid_00000" +
           std::to_string(k) + ".vti\"/>\n";
    pvd += "    <DataSet timestep=\"" + std::to_string(times[k]) + "\" group=\"\" part=\"1\" file=\"" + name + "\"/>\n";
  }
  write(run / "run.pvd", pvd + "  </Collection>\n</VTKFile>\n");
  return run;
}

}  // namespace series_fixture

using namespace suffuse::plot;

vtkSmartPointer<vtkImageData> read_png(const fs::path& file) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  return reader->GetOutput();
}

// How many different colours IMAGE has.
std::size_t colour_count(vtkImageData* image) {
  vtkDataArray* pixels = image->GetPointData()->GetScalars();
  std::set<std::array<int, 3>> colours;
  for (vtkIdType p = 0; p < pixels->GetNumberOfTuples(); ++p)
    colours.insert({static_cast<int>(pixels->GetComponent(p, 0)), static_cast<int>(pixels->GetComponent(p, 1)),
                    static_cast<int>(pixels->GetComponent(p, 2))});
  return colours.size();
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const suffuse::Error& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(PointSeries, ReadsThePointFramesByTimeAndSkipsOtherParts) {
  const fs::path run = series_fixture::write_run(fresh_dir("plot_series"));
  for (const fs::path& path : {run, run / "run.pvd"}) {
    const PointSeries series = read_point_series(path);
    ASSERT_EQ(series.frames.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(series.frames[k].time, series_fixture::times[k]);
      EXPECT_EQ(series.frames[k].file, run / ("run_00000" + std::to_string(k) + ".vtp"));
    }
  }
  EXPECT_NE(error_of([&] { read_point_series(run / "absent"); }).find("does not exist"), std::string::npos);
  write(run / "broken.pvd", "<VTKFile type=\"Collection\"><Collection>");
  EXPECT_NE(error_of([&] { read_point_series(run / "broken.pvd"); }).find("cannot be parsed"), std::string::npos);
}

TEST(PointSeries, NearestFrameAndTheRangeWhenOutside) {
  const PointSeries series = read_point_series(series_fixture::write_run(fresh_dir("plot_nearest")));
  EXPECT_EQ(nearest_frame(series, 0), 0u);
  EXPECT_EQ(nearest_frame(series, 1.2), 1u);
  EXPECT_EQ(nearest_frame(series, 1.8), 2u);
  EXPECT_EQ(nearest_frame(series, 2.5), 2u);
  const std::string error = error_of([&] { nearest_frame(series, 3); });
  EXPECT_NE(error.find("t = 3 s is outside the series"), std::string::npos) << error;
  EXPECT_NE(error.find("from 0 s to 2.5 s"), std::string::npos) << error;
  EXPECT_NE(error_of([&] { nearest_frame(series, -0.1); }).find("outside"), std::string::npos);
}

TEST(PointField, ScalarsComponentsMagnitudesAndUnits) {
  const PointSeries series = read_point_series(series_fixture::write_run(fresh_dir("plot_field")));
  const auto points = read_frame(series.frames[1]);
  const PointField phi = point_field(points, "porosity");
  EXPECT_EQ(phi.label, "porosity [-]");
  EXPECT_DOUBLE_EQ(phi.values[0], series_fixture::porosity(0.05, 1));
  EXPECT_EQ(point_field(points, "velocity:y").values[7], 4);
  EXPECT_EQ(point_field(points, "velocity").values[7], 5);  // magnitude
  EXPECT_EQ(point_field(points, "velocity").label, "velocity magnitude");
  std::string error = error_of([&] { point_field(points, "fines_content"); });
  EXPECT_NE(error.find("no field 'fines_content'; the fields are: porosity, velocity (:x, :y, :z, :magnitude), volume, "
                       "stress (:XX, :YY, :ZZ, :XY, :YZ, :XZ)"),
            std::string::npos)
      << error;
  EXPECT_EQ(point_field(points, "stress:XY").values[3], 0.5);
  EXPECT_EQ(point_field(points, "stress:XY").label, "stress XY");
  error = error_of([&] { point_field(points, "stress"); });
  EXPECT_NE(error.find("field 'stress' has 6 components: name one (stress:XX, stress:YY"), std::string::npos) << error;
  error = error_of([&] { point_field(points, "velocity:w"); });
  EXPECT_NE(error.find("has no component 'w'; expected one of x, y, z, magnitude"), std::string::npos) << error;
  EXPECT_NE(error_of([&] { point_field(points, "porosity:x"); }).find("is a scalar"), std::string::npos);
  // 2D: a square of the point's area.
  EXPECT_NEAR(point_sizes(points)[0][0], 0.1, 1e-15);
  EXPECT_EQ(point_sizes(points)[0][2], 0);
}

TEST(Profile, TakesThePointsWhoseBoxTheLineCrossesInOrder) {
  const PointSeries series = read_point_series(series_fixture::write_run(fresh_dir("plot_profile")));
  const auto points = read_frame(series.frames[2]);
  const auto phi = point_field(points, "porosity");
  const auto sizes = point_sizes(points);
  // Through the middle of the second column of points: its 10 points.
  ProfileLine line{{0.15, 0, 0}, {0.15, 1, 0}, 0};
  auto samples = extract_profile(points, phi.values, sizes, line);
  ASSERT_EQ(samples.size(), 10u);
  for (std::size_t k = 0; k < 10; ++k) {
    const double y = 0.05 + 0.1 * static_cast<double>(k);
    EXPECT_NEAR(samples[k].s, y, 1e-12);
    EXPECT_NEAR(samples[k].value, series_fixture::porosity(y, 2.5), 1e-12);
  }
  // Along the edge between two columns: both, each height twice.
  line.from = {0.2, 0, 0}, line.to = {0.2, 1, 0};
  samples = extract_profile(points, phi.values, sizes, line);
  ASSERT_EQ(samples.size(), 20u);
  EXPECT_NEAR(samples[0].s, 0.05, 1e-12);
  EXPECT_NEAR(samples[1].s, 0.05, 1e-12);
  EXPECT_NEAR(samples[19].value, series_fixture::porosity(0.95, 2.5), 1e-12);
  // Downwards over half the height, with a band of 0.11 m: three columns.
  line = {{0.15, 0.5, 0}, {0.15, 0, 0}, 0.11};
  samples = extract_profile(points, phi.values, sizes, line);
  ASSERT_EQ(samples.size(), 15u);
  EXPECT_NEAR(samples.front().s, 0.05, 1e-12);
  EXPECT_NEAR(samples.front().value, series_fixture::porosity(0.45, 2.5), 1e-12);
  EXPECT_NEAR(samples.back().value, series_fixture::porosity(0.05, 2.5), 1e-12);
  // Beside the body: nothing.
  line = {{0.6, 0, 0}, {0.6, 1, 0}, 0};
  EXPECT_TRUE(extract_profile(points, phi.values, sizes, line).empty());
  line.to = line.from;
  EXPECT_NE(error_of([&] { extract_profile(points, phi.values, sizes, line); }).find("no length"), std::string::npos);
}

TEST(Profile, CommandWritesOnePngPerField) {
  const fs::path dir = fresh_dir("plot_profile_png");
  series_fixture::write_run(dir);
  ASSERT_EQ(plot(dir, "profile --png column.png --field porosity --field velocity:y --from 0.15,0 --to 0.15,1 "
                      "--times 0,1.2,2.5 run"),
            0)
      << slurp(dir / "log.txt");
  const std::string log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("t = 1.2 s: the nearest frame is at t = 1 s"), std::string::npos) << log;
  for (const char* png : {"column.porosity.png", "column.velocity_y.png"}) {
    ASSERT_TRUE(fs::exists(dir / png)) << png;
    const auto image = read_png(dir / png);
    int dims[3];
    image->GetDimensions(dims);
    EXPECT_EQ(dims[0], 900);
    EXPECT_EQ(dims[1], 600);
    EXPECT_GT(colour_count(image), 10u);
  }
  EXPECT_FALSE(fs::exists(dir / "column.png"));
}

TEST(Profile, CommandErrorsWriteNothing) {
  const fs::path dir = fresh_dir("plot_profile_errors");
  series_fixture::write_run(dir);
  struct Case {
    std::string args, message;
  };
  const Case cases[] = {
      {"--field fines --from 0.15,0 --to 0.15,1 run", "no field 'fines'; the fields are: porosity"},
      {"--field porosity --from 0.15,0 --to 0.15,1 --times 0,7 run", "t = 7 s is outside the series"},
      {"--field porosity --from 0.6,0 --to 0.6,1 run", "no material point lies near the line"},
      {"--field porosity --from 0.6,0 --to 0.6,1 run", "widen the band with --band"},
      {"--field porosity --from 0.15 --to 0.15,1 run", "--from 0.15: expected a position X,Y"},
      {"--field porosity --from 0.15,0 --to 0.15,1 nowhere", "nowhere does not exist"},
      {"--field porosity --from 0.15,0 --to 0.15,1", "needs one run"},
  };
  for (const Case& c : cases) {
    EXPECT_EQ(plot(dir, "profile --png out.png " + c.args), 1) << c.args;
    const std::string log = slurp(dir / "log.txt");
    EXPECT_NE(log.find(c.message), std::string::npos) << c.args << "\n" << log;
    EXPECT_FALSE(fs::exists(dir / "out.png")) << c.args;
    EXPECT_FALSE(fs::exists(dir / "out.png.part")) << c.args;
  }
}

TEST(ColourMap, ViridisEnds) {
  EXPECT_NEAR(viridis(0)[0], 68 / 255.0, 1e-12);
  EXPECT_NEAR(viridis(1)[1], 231 / 255.0, 1e-12);
  EXPECT_NEAR(viridis(0.5)[1], 144 / 255.0, 1e-12);
  EXPECT_EQ(viridis(2), viridis(1));
}

TEST(ColourMap, ColoursEachPointByItsValue) {
  const fs::path dir = fresh_dir("plot_map");
  const fs::path run = series_fixture::write_run(dir);
  ASSERT_EQ(plot(dir, "map --png map.png --field porosity --time 2.5 --range 0.3 0.45 --width 400 --height 500 run"),
            0)
      << slurp(dir / "log.txt");
  const auto image = read_png(dir / "map.png");
  int dims[3];
  image->GetDimensions(dims);
  ASSERT_EQ(dims[0], 400);
  ASSERT_EQ(dims[1], 500);
  EXPECT_GT(colour_count(image), 20u);

  // The colour at the centre of a few points is the scale's colour of its value.
  const auto points = read_frame(read_point_series(run).frames[0]);
  const MapLayout layout = map_layout(body_bounds(points), 1, 400, 500);
  EXPECT_EQ(layout.body, (std::array<double, 4>{0, 0.4, 0, 1}));
  vtkDataArray* pixels = image->GetPointData()->GetScalars();
  for (const auto& [x, y] : {std::pair{0.15, 0.05}, std::pair{0.35, 0.55}, std::pair{0.05, 0.95}}) {
    const auto at = layout.pixel(0, x, y);
    const vtkIdType p = static_cast<vtkIdType>(std::floor(at[1])) * dims[0] + static_cast<vtkIdType>(std::floor(at[0]));
    const auto expected = viridis((series_fixture::porosity(y, 2.5) - 0.3) / 0.15);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(pixels->GetComponent(p, c), 255 * expected[c], 4) << "at (" << x << ", " << y << "), channel " << c;
  }
  // Outside the body: the white background.
  const auto outside = layout.pixel(0, 0.45, 0.5);
  const vtkIdType q = static_cast<vtkIdType>(outside[1]) * dims[0] + static_cast<vtkIdType>(outside[0]);
  EXPECT_EQ(pixels->GetComponent(q, 0), 255);
}

TEST(ColourMap, PanelsSizedFromTheBodyAndErrors) {
  const fs::path dir = fresh_dir("plot_map_panels");
  series_fixture::write_run(dir);
  ASSERT_EQ(plot(dir, "map --png map.png --field velocity:x --times 0,1,2.5 run/run.pvd"), 0) << slurp(dir / "log.txt");
  const auto layout = map_layout({0, 0.4, 0, 1}, 3, 0, 0);
  EXPECT_TRUE(layout.in_row);
  int dims[3];
  read_png(dir / "map.png")->GetDimensions(dims);
  EXPECT_EQ(dims[0], layout.width);
  EXPECT_EQ(dims[1], layout.height);

  EXPECT_EQ(plot(dir, "map --png bad.png --field porosity --range 0.5 0.4 run"), 1);
  EXPECT_NE(slurp(dir / "log.txt").find("--range MIN MAX: expected finite numbers with MIN < MAX"), std::string::npos);
  EXPECT_EQ(plot(dir, "map --png bad.png --field porosity --time 9 run"), 1);
  EXPECT_NE(slurp(dir / "log.txt").find("from 0 s to 2.5 s"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "bad.png"));
}

TEST(ColourMap, SlicesOfA3DRun) {
  const fs::path dir = fresh_dir("plot_map_3d");
  const fs::path run = series_fixture::write_run(dir, 3);
  EXPECT_EQ(plot(dir, "map --png map.png --field porosity run"), 1);
  std::string log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("this run is 3D: a colour map shows a slice of it; name one with --slice x=X, y=Y or z=Z "
                     "(the points span x from 0.05 to 0.35, y from 0.05 to 0.95, z from 0.05 to 0.25 m)"),
            std::string::npos)
      << log;
  EXPECT_EQ(plot(dir, "map --png map.png --field porosity --slice z=5 run"), 1);
  log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("no material point's box crosses the plane z = 5 m (the points span 0.05 to 0.25 m)"),
            std::string::npos)
      << log;
  EXPECT_EQ(plot(dir, "map --png map.png --field porosity --slice w=5 run"), 1);
  EXPECT_NE(slurp(dir / "log.txt").find("expected x=X, y=Y or z=Z"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "map.png"));

  // The middle layer, z = 0.15: its colours, not those of the layers beside it.
  ASSERT_EQ(plot(dir, "map --png map.png --field porosity --slice z=0.15 --time 1 --range 0.3 0.5 --width 400 "
                      "--height 500 run"),
            0)
      << slurp(dir / "log.txt");
  const auto image = read_png(dir / "map.png");
  const auto points = read_frame(read_point_series(run).frames[0]);
  const MapPlane plane = map_plane(points, "z=0.15");
  const MapLayout layout = map_layout(body_bounds(points, plane), 1, 400, 500, plane);
  EXPECT_EQ(layout.body, (std::array<double, 4>{0, 0.4, 0, 1}));
  const auto at = layout.pixel(0, 0.25, 0.35);
  const vtkIdType p = static_cast<vtkIdType>(at[1]) * 400 + static_cast<vtkIdType>(at[0]);
  const auto expected = viridis((series_fixture::porosity(0.35, 1, 0.15) - 0.3) / 0.2);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(image->GetPointData()->GetScalars()->GetComponent(p, c), 255 * expected[c], 4) << c;

  // Across y: x horizontal, z vertical.
  EXPECT_EQ(body_bounds(points, map_plane(points, "y=0.5")), (std::array<double, 4>{0, 0.4, 0, 0.3}));
  ASSERT_EQ(plot(dir, "animate --field porosity --slice y=0.5 --frames frames run"), 0) << slurp(dir / "log.txt");

  // A 2D run has no slice.
  const fs::path flat = fresh_dir("plot_map_2d_slice");
  series_fixture::write_run(flat);
  EXPECT_EQ(plot(flat, "map --png map.png --field porosity --slice z=0 run"), 1);
  EXPECT_NE(slurp(flat / "log.txt").find("this run is 2D"), std::string::npos);
}

TEST(Animation, OneFramePerOutputAndALoopingGif) {
  const fs::path dir = fresh_dir("plot_animate");
  series_fixture::write_run(dir);
  ASSERT_EQ(plot(dir, "animate --field porosity --frames frames --gif porosity.gif run"), 0)
      << slurp(dir / "log.txt");
  std::size_t pngs = 0;
  for (const auto& e : fs::directory_iterator(dir / "frames")) pngs += e.path().extension() == ".png";
  EXPECT_EQ(pngs, 3u);
  EXPECT_TRUE(fs::exists(frame_png(dir / "frames", "porosity", 2)));

  int error = 0;
  GifFileType* gif = DGifOpenFileName((dir / "porosity.gif").c_str(), &error);
  ASSERT_NE(gif, nullptr);
  ASSERT_EQ(DGifSlurp(gif), GIF_OK);
  EXPECT_EQ(gif->ImageCount, 3);
  int dims[3];
  read_png(frame_png(dir / "frames", "porosity", 0))->GetDimensions(dims);
  EXPECT_EQ(gif->SWidth, dims[0]);
  EXPECT_EQ(gif->SHeight, dims[1]);
  // The porosity grows with time: the first and last frames differ.
  const std::size_t pixels = static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]);
  EXPECT_FALSE(std::equal(gif->SavedImages[0].RasterBits, gif->SavedImages[0].RasterBits + pixels,
                          gif->SavedImages[2].RasterBits));
  DGifCloseFile(gif, &error);

  // Every second frame, and the last.
  ASSERT_EQ(plot(dir, "animate --field porosity --frames every --every 2 --range -1 1 run"), 0)
      << slurp(dir / "log.txt");
  pngs = 0;
  for (const auto& e : fs::directory_iterator(dir / "every")) pngs += e.path().extension() == ".png";
  EXPECT_EQ(pngs, 2u);

  EXPECT_EQ(plot(dir, "animate --field porosity run"), 1);
  EXPECT_NE(slurp(dir / "log.txt").find("needs --frames DIR"), std::string::npos);
  EXPECT_EQ(plot(dir, "animate --field fines --frames none run"), 1);
  EXPECT_FALSE(fs::exists(dir / "none"));
}

}  // namespace

namespace {

// The default scene for a moment, then its figures: the fields carry their
// units, and the boxes come from the points' volumes.
TEST(PointSeries, FiguresOfARealRun) {
  const fs::path dir = fresh_dir("plot_real_run");
  auto scene = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/suffusion_column.json");
  scene["time"]["end"] = 0.3;
  scene["outputs"][0]["interval"] = 0.1;
  std::ofstream(dir / "column.json") << scene.dump(2);
  const std::string run = "cd " + dir.string() + " && " + SUFFUSE_EXECUTABLE + " run column.json --quiet > run.txt 2>&1";
  ASSERT_EQ(std::system(run.c_str()), 0) << slurp(dir / "run.txt");

  const PointSeries series = read_point_series(dir / "output/column");
  ASSERT_GE(series.frames.size(), 4u);
  const auto points = read_frame(series.frames.back());
  EXPECT_EQ(point_field(points, "porosity").label, "porosity [-]");
  EXPECT_EQ(point_field(points, "velocity:y").label, "velocity y [m/s]");
  // 8 x 80 points of 5 mm over the 4 cm x 40 cm column.
  const auto body = body_bounds(points);
  EXPECT_NEAR(body[1] - body[0], 0.04, 1e-3);
  EXPECT_NEAR(body[3] - body[2], 0.4, 1e-3);
  // The axis: two columns of points, each height twice.
  const auto profile = extract_profile(points, point_field(points, "porosity").values, point_sizes(points),
                                       {{0.02, 0, 0}, {0.02, 0.4, 0}, 0});
  EXPECT_EQ(profile.size(), 160u);

  ASSERT_EQ(plot(dir, "profile --png axis.png --field porosity --field fines_content --from 0.02,0 --to 0.02,0.4 "
                      "output/column"),
            0)
      << slurp(dir / "log.txt");
  EXPECT_TRUE(fs::exists(dir / "axis.porosity.png"));
  EXPECT_TRUE(fs::exists(dir / "axis.fines_content.png"));
  ASSERT_EQ(plot(dir, "map --png map.png --field fines_content --times 0,0.3 output/column"), 0)
      << slurp(dir / "log.txt");
  EXPECT_GT(colour_count(read_png(dir / "map.png")), 20u);
}

}  // namespace
