// suffuse plot: line charts of CSV columns drawn offscreen (no display) and
// written as PNG; read back with VTK's PNG reader.
#include <gtest/gtest.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>

#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("suffuse_plot_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void write(const fs::path& file, const std::string& text) { std::ofstream(file) << text; }

std::string slurp(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

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
  const fs::path dir = fresh_dir("png");
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
  const fs::path dir = fresh_dir("column");
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
  const fs::path dir = fresh_dir("missing");
  write(dir / "growth.csv", growth);
  EXPECT_EQ(plot(dir, "--png chart.png --x time --y height growth.csv absent.csv"), 1);
  const std::string log = slurp(dir / "log.txt");
  EXPECT_NE(log.find("absent.csv"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(dir / "chart.png"));
}

TEST(Plot, BadCellsAndEmptyFilesFail) {
  const fs::path dir = fresh_dir("bad");
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
