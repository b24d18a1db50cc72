// suffuse plot: line charts of CSV columns to PNG, without a display.
//
// The Debian VTK 9.1 is built for X only (vtkXOpenGLRenderWindow, no OSMesa or
// EGL window): without $DISPLAY its vtkRenderWindow aborts, offscreen or not.
// So the chart is drawn into a vtkGenericOpenGLRenderWindow whose OpenGL
// context comes from EGL (Mesa's surfaceless platform, a pbuffer of the image
// size), which needs no X server and no GPU (Mesa falls back to software).
#include "plot.hpp"

// GLEW first: it must come before any other OpenGL header.
#include <vtk_glew.h>

#define EGL_NO_X11  // keep Xlib's macros (None, Bool, Status) out
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>
#include <vtkPNGWriter.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkTextRenderer.h>
#include <vtkWindowToImageFilter.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <suffuse/error.hpp>
#include <system_error>

namespace suffuse::plot {

namespace fs = std::filesystem;

namespace {

// ---------------------------------------------------------------- CSV input

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

// One line of comma-separated cells; a cell may be quoted ("a, b", "say ""x""").
std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') cells.back() += '"', ++i;
      else if (c == '"') quoted = false;
      else cells.back() += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      cells.emplace_back();
    } else {
      cells.back() += c;
    }
  }
  for (auto& cell : cells) cell = trim(cell);
  return cells;
}

struct CsvFile {
  fs::path path;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::size_t> line_numbers;  // of each row in the file, from 1 (the header is line 1)
};

CsvFile read_csv(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error("cannot read " + path.string() + ": no such file");
  if (fs::is_directory(path, ec)) throw Error("cannot read " + path.string() + ": it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read " + path.string());
  CsvFile csv{path, {}, {}, {}};
  std::string line;
  std::size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (trim(line).empty()) continue;
    if (csv.header.empty()) {
      if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte order mark
      csv.header = split_csv_line(line);
      continue;
    }
    csv.rows.push_back(split_csv_line(line));
    csv.line_numbers.push_back(number);
  }
  if (in.bad()) throw Error("cannot read " + path.string());
  if (csv.header.empty()) throw Error(path.string() + " is empty (a header row and data rows were expected)");
  if (csv.rows.empty()) throw Error(path.string() + " has a header but no data rows");
  return csv;
}

std::string list_columns(const std::vector<std::string>& header) {
  std::string s;
  for (const auto& h : header) s += (s.empty() ? "" : ", ") + ("'" + h + "'");
  return s;
}

// The column NAME matches exactly, or by the part of the header before " [" (its unit).
std::size_t find_column(const CsvFile& csv, const std::string& name) {
  for (std::size_t c = 0; c < csv.header.size(); ++c)
    if (csv.header[c] == name) return c;
  std::vector<std::size_t> found;
  for (std::size_t c = 0; c < csv.header.size(); ++c) {
    const auto bracket = csv.header[c].find(" [");
    if (bracket != std::string::npos && trim(csv.header[c].substr(0, bracket)) == name) found.push_back(c);
  }
  if (found.size() == 1) return found[0];
  if (found.empty())
    throw Error(csv.path.string() + " has no column '" + name + "'; its columns are: " + list_columns(csv.header));
  std::vector<std::string> names;
  for (auto c : found) names.push_back(csv.header[c]);
  throw Error("column '" + name + "' is ambiguous in " + csv.path.string() + ": " + list_columns(names) +
              "; give the whole header");
}

double parse_cell(const CsvFile& csv, std::size_t row, std::size_t column) {
  const auto& cells = csv.rows[row];
  const std::string where = csv.path.string() + ", line " + std::to_string(csv.line_numbers[row]);
  if (column >= cells.size())
    throw Error(where + " has " + std::to_string(cells.size()) + " cell(s) but the header has " +
                std::to_string(csv.header.size()) + "; column '" + csv.header[column] + "' is missing");
  const std::string& text = cells[column];
  const char* begin = text.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  if (text.empty() || end != begin + text.size())
    throw Error(where + ", column '" + csv.header[column] + "': '" + text + "' is not a number");
  return v;
}

// ---------------------------------------------------------------- series

struct Series {
  std::string label;
  std::vector<double> x, y;
};

// File stems for the legend. With several files, the leading and trailing
// parts that all stems share are dropped, cut at a '.', '-' or ' ' that is not
// a decimal point (so scene.eta_0.element and scene.eta_0.3.element give eta_0
// and eta_0.3), unless a stem would be left empty.
std::vector<std::string> legend_names(const std::vector<fs::path>& files, bool full) {
  std::vector<std::string> stems;
  for (const auto& f : files) stems.push_back(f.stem().string());
  if (std::set<std::string>(stems.begin(), stems.end()).size() != stems.size()) {
    // Same stem in different directories: the paths tell them apart.
    stems.clear();
    for (const auto& f : files) stems.push_back((f.parent_path() / f.stem()).string());
    return stems;
  }
  if (full || stems.size() < 2) return stems;
  auto digit = [](const std::string& s, std::size_t i) {
    return i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]));
  };
  // Whether position I of S separates words.
  auto is_cut = [&](const std::string& s, std::size_t i) {
    const char c = s[i];
    if (c == '-' || c == ' ') return true;
    return c == '.' && !(i > 0 && digit(s, i - 1) && digit(s, i + 1));
  };
  // The longest common prefix that ends with a cut in every stem.
  std::size_t prefix = 0;
  for (std::size_t i = 0;; ++i) {
    bool same = true, cut = true;
    for (const auto& s : stems) {
      same = same && i < s.size() && s[i] == stems[0][i];
      cut = cut && same && is_cut(s, i);
    }
    if (!same) break;
    if (cut) prefix = i + 1;
  }
  // The longest common suffix that starts with a cut in every stem.
  std::size_t suffix = 0;
  for (std::size_t i = 0;; ++i) {
    bool same = true, cut = true;
    for (const auto& s : stems) {
      same = same && i < s.size() && s[s.size() - 1 - i] == stems[0][stems[0].size() - 1 - i];
      cut = cut && same && is_cut(s, s.size() - 1 - i);
    }
    if (!same) break;
    if (cut) suffix = i + 1;
  }
  auto strip = [&](std::size_t p, std::size_t q) {
    std::vector<std::string> out;
    for (const auto& s : stems) {
      if (p + q >= s.size()) return std::vector<std::string>();
      out.push_back(s.substr(p, s.size() - p - q));
    }
    return out;
  };
  for (auto [p, q] : {std::pair{prefix, suffix}, std::pair{prefix, std::size_t{0}}, std::pair{std::size_t{0}, suffix}}) {
    auto out = strip(p, q);
    if (!out.empty()) return out;
  }
  return stems;
}

std::string format_number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

std::string scaled_label(const std::string& header, double scale) {
  return scale == 1 ? header : header + " (x" + format_number(scale) + ")";
}

// The corner of the plot area crossed by the fewest lines.
LegendCorner choose_corner(const std::vector<Series>& series) {
  double x0 = std::numeric_limits<double>::max(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const auto& s : series)
    for (std::size_t i = 0; i < s.x.size(); ++i)
      x0 = std::min(x0, s.x[i]), x1 = std::max(x1, s.x[i]), y0 = std::min(y0, s.y[i]), y1 = std::max(y1, s.y[i]);
  const double dx = x1 > x0 ? x1 - x0 : 1, dy = y1 > y0 ? y1 - y0 : 1;
  // The legend box as a fraction of the plot area: a column of entries.
  const double w = 0.4, h = std::min(0.7, 0.07 * static_cast<double>(series.size()) + 0.06);
  std::array<std::size_t, 4> count{};  // top-right, top-left, bottom-right, bottom-left
  auto add = [&](double x, double y) {
    const double u = (x - x0) / dx, v = (y - y0) / dy;
    if (v >= 1 - h && u >= 1 - w) ++count[0];
    if (v >= 1 - h && u <= w) ++count[1];
    if (v <= h && u >= 1 - w) ++count[2];
    if (v <= h && u <= w) ++count[3];
  };
  for (const auto& s : series)
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      add(s.x[i], s.y[i]);
      if (i + 1 < s.x.size())  // points along each segment, so sparse data counts too
        for (int k = 1; k < 8; ++k)
          add(s.x[i] + (s.x[i + 1] - s.x[i]) * k / 8, s.y[i] + (s.y[i + 1] - s.y[i]) * k / 8);
    }
  const std::array<LegendCorner, 4> corners{LegendCorner::top_right, LegendCorner::top_left,
                                            LegendCorner::bottom_right, LegendCorner::bottom_left};
  return corners[std::min_element(count.begin(), count.end()) - count.begin()];
}

// ---------------------------------------------------------------- VTK messages

// Collects VTK's errors and warnings (they would otherwise go to the terminal
// through its logger) so that a failed rendering becomes a suffuse error.
class CollectingOutputWindow : public vtkOutputWindow {
 public:
  static CollectingOutputWindow* New();
  vtkTypeMacro(CollectingOutputWindow, vtkOutputWindow)
  void DisplayText(const char*) override {}
  void DisplayErrorText(const char* text) override { errors.push_back(clean(text)); }
  void DisplayWarningText(const char* text) override { warnings.push_back(clean(text)); }
  void DisplayGenericWarningText(const char* text) override { warnings.push_back(clean(text)); }
  void DisplayDebugText(const char*) override {}
  std::vector<std::string> errors, warnings;

 private:
  // "ERROR: In file.cxx, line N\nvtkClass (0x...): message\n\n" -> "vtkClass: message"
  static std::string clean(std::string text) {
    if (text.rfind("ERROR: In ", 0) == 0 || text.rfind("Warning: In ", 0) == 0 ||
        text.rfind("Generic Warning: In ", 0) == 0) {
      const auto nl = text.find('\n');
      if (nl != std::string::npos) text.erase(0, nl + 1);
    }
    const auto open = text.find(" (0x");
    const auto close = text.find("): ", open == std::string::npos ? 0 : open);
    if (open != std::string::npos && close != std::string::npos) text.erase(open, close + 1 - open);
    return trim(text.substr(0, text.find_last_not_of('\n') + 1));
  }
};
vtkStandardNewMacro(CollectingOutputWindow)

// Installs a CollectingOutputWindow for its lifetime.
class VtkMessages {
 public:
  VtkMessages() : previous_(vtkOutputWindow::GetInstance()) {
    // VTK's logger would print every error a second time, in colour (for the whole process).
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
    vtkOutputWindow::SetInstance(window_);
  }
  ~VtkMessages() { vtkOutputWindow::SetInstance(previous_); }
  VtkMessages(const VtkMessages&) = delete;
  VtkMessages& operator=(const VtkMessages&) = delete;
  // Throws the first error VTK reported, if any.
  void check(const std::string& what) const {
    if (!window_->errors.empty()) throw Error(what + ": " + window_->errors.front());
  }
  // Prints VTK's warnings, if any.
  void report_warnings() const {
    for (const auto& w : window_->warnings) std::cerr << "suffuse: VTK warning: " << w << "\n";
  }

 private:
  vtkSmartPointer<vtkOutputWindow> previous_;
  vtkNew<CollectingOutputWindow> window_;
};

// ---------------------------------------------------------------- EGL context

std::string egl_error() {
  const EGLint e = eglGetError();
  switch (e) {
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    default: {
      std::ostringstream s;
      s << "EGL error 0x" << std::hex << e;
      return s.str();
    }
  }
}

// An OpenGL context on a pbuffer of the image size, from EGL without a window
// system: Mesa's surfaceless platform, else the first EGL device, else the
// default display.
class EglContext {
 public:
  EglContext(int width, int height) {
    std::string tried;
    const char* ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    const std::string client = ext ? ext : "";
    auto has = [&](const char* name) { return (" " + client + " ").find(std::string(" ") + name + " ") != std::string::npos; };
    auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));

    std::vector<std::pair<std::string, EGLDisplay>> candidates;
    if (get_platform_display && has("EGL_MESA_platform_surfaceless"))
      candidates.emplace_back("surfaceless",
                              get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr));
    if (get_platform_display && has("EGL_EXT_platform_device")) {
      auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
      EGLDeviceEXT devices[4];
      EGLint n = 0;
      if (query_devices && query_devices(4, devices, &n) && n > 0)
        candidates.emplace_back("device", get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[0], nullptr));
    }
    candidates.emplace_back("default display", eglGetDisplay(EGL_DEFAULT_DISPLAY));

    for (const auto& [name, display] : candidates) {
      if (display == EGL_NO_DISPLAY) {
        tried += (tried.empty() ? "" : "; ") + name + ": no display";
        continue;
      }
      std::string why;
      if (open(display, width, height, why)) return;
      tried += (tried.empty() ? "" : "; ") + name + ": " + why;
    }
    throw Error("cannot create an offscreen OpenGL context with EGL (" + tried +
                "); suffuse plot needs libEGL with Mesa (Debian packages libegl1, libegl-mesa0, libgl1-mesa-dri)");
  }
  ~EglContext() { close(); }
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  void make_current() const { eglMakeCurrent(display_, surface_, surface_, context_); }
  bool is_current() const { return context_ != EGL_NO_CONTEXT && eglGetCurrentContext() == context_; }

 private:
  bool open(EGLDisplay display, int width, int height, std::string& why) {
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) return why = "eglInitialize: " + egl_error(), false;
    display_ = display;
    if (!eglBindAPI(EGL_OPENGL_API)) return why = "no desktop OpenGL: " + egl_error(), close(), false;
    const EGLint config_attributes[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                                        EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_ALPHA_SIZE, 8,
                                        EGL_DEPTH_SIZE, 24, EGL_NONE};
    EGLConfig config;
    EGLint configs = 0;
    if (!eglChooseConfig(display_, config_attributes, &config, 1, &configs) || configs < 1)
      return why = "no RGBA pbuffer configuration for OpenGL", close(), false;
    const EGLint surface_attributes[] = {EGL_WIDTH, width, EGL_HEIGHT, height, EGL_NONE};
    surface_ = eglCreatePbufferSurface(display_, config, surface_attributes);
    if (surface_ == EGL_NO_SURFACE) return why = "eglCreatePbufferSurface: " + egl_error(), close(), false;
    // VTK needs OpenGL 3.2; a core profile gets it from every Mesa driver.
    const EGLint core[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 2,
                           EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, core);
    if (context_ == EGL_NO_CONTEXT) context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, nullptr);
    if (context_ == EGL_NO_CONTEXT) return why = "eglCreateContext: " + egl_error(), close(), false;
    if (!eglMakeCurrent(display_, surface_, surface_, context_))
      return why = "eglMakeCurrent: " + egl_error(), close(), false;
    return true;
  }
  void close() {
    if (display_ == EGL_NO_DISPLAY) return;
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
    if (surface_ != EGL_NO_SURFACE) eglDestroySurface(display_, surface_);
    eglTerminate(display_);
    display_ = EGL_NO_DISPLAY, surface_ = EGL_NO_SURFACE, context_ = EGL_NO_CONTEXT;
  }
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLSurface surface_ = EGL_NO_SURFACE;
  EGLContext context_ = EGL_NO_CONTEXT;
};

// A VTK render window drawing into an EglContext.
class EglRenderWindow : public vtkGenericOpenGLRenderWindow {
 public:
  static EglRenderWindow* New();
  vtkTypeMacro(EglRenderWindow, vtkGenericOpenGLRenderWindow)

  void attach(const EglContext* context) {
    context_ = context;
    this->SetReadyForRendering(context != nullptr);
  }
  void MakeCurrent() override {
    if (context_) context_->make_current();
  }
  bool IsCurrent() override { return context_ && context_->is_current(); }
  // As vtkOpenGLRenderWindow's, but GLEW built for GLX (Debian's) reports
  // GLEW_ERROR_NO_GLX_DISPLAY under EGL after it has loaded every OpenGL entry
  // point; only its GLX extensions are missing, which VTK does not use here.
  void OpenGLInitContext() override {
    this->ContextCreationTime.Modified();
    if (this->Initialized) return;
    const GLenum result = glewInit();
    if (result != GLEW_OK && result != GLEW_ERROR_NO_GLX_DISPLAY) {
      vtkErrorMacro("GLEW could not be initialized: " << reinterpret_cast<const char*>(glewGetErrorString(result)));
      return;
    }
    if (!GLEW_VERSION_3_2 && !GLEW_VERSION_3_1) {
      vtkErrorMacro("the EGL context has no OpenGL 3.2 (" << reinterpret_cast<const char*>(glGetString(GL_VERSION))
                                                           << ")");
      return;
    }
    this->GlewInitValid = true;
    this->Initialized = true;
    GLfloat range[2];
    this->MaximumHardwareLineWidth = 1.0;
    glGetFloatv(this->LineSmoothing ? GL_SMOOTH_LINE_WIDTH_RANGE : GL_ALIASED_LINE_WIDTH_RANGE, range);
    if (glGetError() == GL_NO_ERROR) this->MaximumHardwareLineWidth = range[1];
  }

 protected:
  EglRenderWindow() = default;
  ~EglRenderWindow() override {
    // Free VTK's OpenGL objects while the context is still there.
    if (context_) {
      context_->make_current();
      this->Finalize();
    }
  }

 private:
  const EglContext* context_ = nullptr;
};
vtkStandardNewMacro(EglRenderWindow)

// Colours that stay apart on white (Tableau 10); after ten lines the dash changes.
constexpr std::array<std::array<unsigned char, 3>, 10> palette{{{31, 119, 180},
                                                                 {255, 127, 14},
                                                                 {44, 160, 44},
                                                                 {214, 39, 40},
                                                                 {148, 103, 189},
                                                                 {140, 86, 75},
                                                                 {227, 119, 194},
                                                                 {127, 127, 127},
                                                                 {188, 189, 34},
                                                                 {23, 190, 207}}};
constexpr std::array<int, 4> dashes{vtkPen::SOLID_LINE, vtkPen::DASH_LINE, vtkPen::DOT_LINE, vtkPen::DASH_DOT_LINE};

// DejaVu Sans when installed (Debian's fonts-dejavu-core), else VTK's built-in
// sans-serif font (whose Debian build draws '[' and ']' as parentheses).
void style_text(vtkTextProperty* t, int size, bool bold) {
  static const fs::path dejavu = "/usr/share/fonts/truetype/dejavu";
  const fs::path font = dejavu / (bold ? "DejaVuSans-Bold.ttf" : "DejaVuSans.ttf");
  std::error_code ec;
  if (fs::is_regular_file(font, ec)) {
    t->SetFontFamily(VTK_FONT_FILE);
    t->SetFontFile(font.c_str());
  } else {
    t->SetFontFamilyToArial();
    t->SetBold(bold);
  }
  t->SetFontSize(size);
  t->SetColor(0, 0, 0);
}

// Shrinks the font of T until TEXT is at most LENGTH pixels long (down to 10
// points); whether it changed.
bool fit_text(vtkTextProperty* t, const std::string& text, double length, int dpi) {
  vtkTextRenderer* renderer = vtkTextRenderer::GetInstance();
  if (!renderer || text.empty()) return false;
  vtkNew<vtkTextProperty> flat;
  flat->ShallowCopy(t);
  flat->SetOrientation(0);
  const int size = t->GetFontSize();
  int fit = size;
  for (; fit > 10; --fit) {
    flat->SetFontSize(fit);
    int box[4];
    if (!renderer->GetBoundingBox(flat, text, box, dpi)) return false;
    if (box[1] - box[0] <= length) break;
  }
  t->SetFontSize(fit);
  return fit != size;
}

// Draws the series and writes the PNG to FILE.
void render(const std::vector<Series>& series, const PlotOptions& o, const std::string& xlabel,
            const std::string& ylabel, const fs::path& file) {
  VtkMessages messages;
  EglContext context(o.width, o.height);

  vtkNew<EglRenderWindow> window;
  window->attach(&context);
  window->SetSize(o.width, o.height);
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(8);
  window->InitializeFromCurrentContext();
  messages.check("cannot initialise OpenGL");

  {
    vtkNew<vtkContextView> view;
    view->SetRenderWindow(window);
    view->GetRenderer()->SetBackground(1, 1, 1);

    vtkNew<vtkChartXY> chart;
    view->GetScene()->AddItem(chart);
    // A margin around the chart for the tick labels that stand out at the ends of the axes.
    chart->SetLayoutStrategy(vtkChart::FILL_RECT);
    chart->SetSize(vtkRectf(10, 10, static_cast<float>(o.width - 35), static_cast<float>(o.height - 25)));
    if (!o.title.empty()) {
      chart->SetTitle(o.title);
      style_text(chart->GetTitleProperties(), 20, true);
    }
    const std::pair<int, const std::string*> axes[] = {{vtkAxis::BOTTOM, &xlabel}, {vtkAxis::LEFT, &ylabel}};
    for (const auto& [which, label] : axes) {
      vtkAxis* axis = chart->GetAxis(which);
      axis->SetTitle(*label);
      style_text(axis->GetTitleProperties(), 18, true);
      style_text(axis->GetLabelProperties(), 15, false);
      axis->GetPen()->SetColor(0, 0, 0);
      axis->GetGridPen()->SetColor(225, 225, 225);
    }
    // Axis ranges a little wider than the data, so that lines along an end of
    // the range stay whole; a flat line gets +-10 % of its value.
    for (const int which : {vtkAxis::BOTTOM, vtkAxis::LEFT}) {
      double lo = std::numeric_limits<double>::max(), hi = -lo;
      for (const auto& s : series)
        for (double v : which == vtkAxis::BOTTOM ? s.x : s.y) lo = std::min(lo, v), hi = std::max(hi, v);
      const double span = hi - lo;
      const double pad = span > 1e-12 * std::max(std::abs(lo), std::abs(hi)) ? 0.02 * span
                         : lo == 0                                            ? 1
                                                                              : 0.1 * std::abs(lo);
      chart->GetAxis(which)->SetBehavior(vtkAxis::FIXED);
      chart->GetAxis(which)->SetRange(lo - pad, hi + pad);
    }

    for (std::size_t i = 0; i < series.size(); ++i) {
      const Series& s = series[i];
      vtkNew<vtkDoubleArray> x, y;
      x->SetName(xlabel.c_str());
      y->SetName(s.label.c_str());
      x->SetNumberOfValues(static_cast<vtkIdType>(s.x.size()));
      y->SetNumberOfValues(static_cast<vtkIdType>(s.y.size()));
      for (std::size_t k = 0; k < s.x.size(); ++k) {
        x->SetValue(static_cast<vtkIdType>(k), s.x[k]);
        y->SetValue(static_cast<vtkIdType>(k), s.y[k]);
      }
      vtkNew<vtkTable> table;  // the plot keeps a reference
      table->AddColumn(x);
      table->AddColumn(y);
      vtkPlot* line = chart->AddPlot(vtkChart::LINE);
      line->SetInputData(table, 0, 1);
      line->SetLabel(s.label);
      const auto& c = palette[i % palette.size()];
      line->SetColor(c[0], c[1], c[2], 255);
      line->SetWidth(2.5);
      line->GetPen()->SetLineType(dashes[(i / palette.size()) % dashes.size()]);
    }

    chart->SetShowLegend(true);
    vtkChartLegend* legend = chart->GetLegend();
    style_text(legend->GetLabelProperties(), 15, false);
    legend->SetSymbolWidth(30);
    const LegendCorner corner = o.legend == LegendCorner::automatic ? choose_corner(series) : o.legend;
    const bool left = corner == LegendCorner::top_left || corner == LegendCorner::bottom_left;
    const bool bottom = corner == LegendCorner::bottom_left || corner == LegendCorner::bottom_right;
    legend->SetHorizontalAlignment(left ? vtkChartLegend::LEFT : vtkChartLegend::RIGHT);
    legend->SetVerticalAlignment(bottom ? vtkChartLegend::BOTTOM : vtkChartLegend::TOP);

    window->Render();
    messages.check("cannot draw the chart");
    // Titles longer than the plot area get a smaller font (the layout follows).
    const int* p1 = chart->GetPoint1();
    const int* p2 = chart->GetPoint2();
    const int dpi = window->GetDPI();
    bool refit = fit_text(chart->GetAxis(vtkAxis::BOTTOM)->GetTitleProperties(), xlabel, p2[0] - p1[0], dpi);
    refit = fit_text(chart->GetAxis(vtkAxis::LEFT)->GetTitleProperties(), ylabel, p2[1] - p1[1] + 20, dpi) || refit;
    refit = fit_text(chart->GetTitleProperties(), o.title, o.width - 20, dpi) || refit;
    if (refit) {
      window->Render();
      messages.check("cannot draw the chart");
    }
    // VTK puts the legend right into the corner, on the axis lines: move it
    // inwards a little and draw again.
    const float inset = 8;
    vtkVector2f at = legend->GetPointVector();
    at.SetX(at.GetX() + (left ? inset : -inset));
    at.SetY(at.GetY() + (bottom ? inset : -inset));
    legend->SetHorizontalAlignment(vtkChartLegend::CUSTOM);
    legend->SetVerticalAlignment(vtkChartLegend::CUSTOM);
    legend->SetPoint(at);
    window->Render();
    messages.check("cannot draw the chart");

    vtkNew<vtkWindowToImageFilter> grab;
    grab->SetInput(window);
    grab->SetInputBufferTypeToRGB();
    grab->ReadFrontBufferOff();
    grab->ShouldRerenderOff();
    grab->Update();
    messages.check("cannot read the image back");
    int dims[3];
    grab->GetOutput()->GetDimensions(dims);
    if (dims[0] != o.width || dims[1] != o.height)
      throw Error("the image read back is " + std::to_string(dims[0]) + " x " + std::to_string(dims[1]) +
                  " pixels, not " + std::to_string(o.width) + " x " + std::to_string(o.height));

    vtkNew<vtkPNGWriter> writer;
    writer->SetFileName(file.c_str());
    writer->SetInputConnection(grab->GetOutputPort());
    writer->Write();
    messages.check("cannot write " + file.string());
    if (writer->GetErrorCode() != 0) throw Error("cannot write " + file.string());
  }
  messages.report_warnings();
}

}  // namespace

LegendCorner parse_legend_corner(const std::string& name) {
  static const std::map<std::string, LegendCorner> corners{{"auto", LegendCorner::automatic},
                                                           {"top-left", LegendCorner::top_left},
                                                           {"top-right", LegendCorner::top_right},
                                                           {"bottom-left", LegendCorner::bottom_left},
                                                           {"bottom-right", LegendCorner::bottom_right}};
  const auto it = corners.find(name);
  if (it == corners.end())
    throw Error("--legend " + name + ": expected auto, top-left, top-right, bottom-left or bottom-right");
  return it->second;
}

void write_plot(const PlotOptions& o) {
  if (o.png.empty()) throw Error("suffuse plot needs --png OUT.png");
  if (o.x.empty()) throw Error("suffuse plot needs --x COLUMN");
  if (o.y.empty()) throw Error("suffuse plot needs at least one --y COLUMN");
  if (o.files.empty()) throw Error("suffuse plot needs at least one CSV file");
  constexpr int max_pixels = 10000;
  if (o.width < 100 || o.width > max_pixels || o.height < 100 || o.height > max_pixels)
    throw Error("--width and --height must be between 100 and " + std::to_string(max_pixels) + " pixels");
  if (!std::isfinite(o.scale_x) || !std::isfinite(o.scale_y) || o.scale_x == 0 || o.scale_y == 0)
    throw Error("--scale-x and --scale-y must be finite and not zero");
  const fs::path dir = o.png.has_parent_path() ? o.png.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error("cannot write " + o.png.string() + ": no directory " + dir.string());
  if (fs::is_directory(o.png, ec)) throw Error("cannot write " + o.png.string() + ": it is a directory");

  // Read and check everything before drawing anything.
  const std::vector<std::string> names = legend_names(o.files, o.full_names);
  std::vector<Series> series;
  std::string x_header;
  std::vector<std::string> y_headers;
  for (std::size_t f = 0; f < o.files.size(); ++f) {
    const CsvFile csv = read_csv(o.files[f]);
    const std::size_t xc = find_column(csv, o.x);
    if (f == 0) x_header = csv.header[xc];
    for (std::size_t j = 0; j < o.y.size(); ++j) {
      const std::size_t yc = find_column(csv, o.y[j]);
      if (f == 0) y_headers.push_back(csv.header[yc]);
      Series s;
      s.label = o.files.size() == 1 ? o.y[j] : o.y.size() == 1 ? names[f] : names[f] + ": " + o.y[j];
      for (std::size_t r = 0; r < csv.rows.size(); ++r) {
        const double x = parse_cell(csv, r, xc) * o.scale_x, y = parse_cell(csv, r, yc) * o.scale_y;
        if (std::isfinite(x) && std::isfinite(y)) s.x.push_back(x), s.y.push_back(y);  // nan, inf: skipped
      }
      if (s.x.empty())
        throw Error(csv.path.string() + ": no row has finite values of both '" + csv.header[xc] + "' and '" +
                    csv.header[yc] + "'");
      series.push_back(std::move(s));
    }
  }
  const std::string xlabel = o.xlabel.empty() ? scaled_label(x_header, o.scale_x) : o.xlabel;
  std::string ylabel = o.ylabel;
  if (ylabel.empty()) {
    for (const auto& h : y_headers) ylabel += (ylabel.empty() ? "" : ", ") + h;
    ylabel = scaled_label(ylabel, o.scale_y);
  }

  // Draw into OUT.png.part, then rename: a reader never sees half a file.
  const fs::path part = o.png.string() + ".part";
  try {
    render(series, o, xlabel, ylabel, part);
    fs::rename(part, o.png);
  } catch (const std::exception& e) {
    fs::remove(part, ec);
    if (dynamic_cast<const Error*>(&e)) throw;
    throw Error("cannot write " + o.png.string() + ": " + e.what());
  }
}

}  // namespace suffuse::plot
