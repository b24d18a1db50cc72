// An offscreen OpenGL render window for VTK from EGL (see offscreen_render_window.hpp).
#include "offscreen_render_window.hpp"

// GLEW first: it must come before any other OpenGL header (the header above includes none).
#include <vtk_glew.h>

#define EGL_NO_X11  // keep Xlib's macros (None, Bool, Status) out
#include <EGL/egl.h>
#include <EGL/eglext.h>
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SUFFUSE_ASAN 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__) || defined(SUFFUSE_ASAN)
#include <dlfcn.h>
#include <link.h>
#endif

#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>

#include <iostream>
#include <sstream>
#include <string_view>
#include <suffuse/error.hpp>
#include <utility>
#include <vector>

namespace suffuse::render {

namespace {

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

}  // namespace

// ---------------------------------------------------------------- VTK messages

// Keeps VTK's errors and warnings for VtkMessages.
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

VtkMessages::VtkMessages()
    : previous_(vtkOutputWindow::GetInstance()), window_(vtkSmartPointer<CollectingOutputWindow>::New()) {
  // VTK's logger would print every error a second time, in colour (for the whole process).
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  vtkOutputWindow::SetInstance(window_);
}

VtkMessages::~VtkMessages() { vtkOutputWindow::SetInstance(previous_); }

void VtkMessages::check(const std::string& what) const {
  if (!window_->errors.empty()) throw Error(what + ": " + window_->errors.front());
}

void VtkMessages::report_warnings() const {
  for (const auto& w : window_->warnings) std::cerr << "suffuse: VTK warning: " << w << "\n";
}

// ---------------------------------------------------------------- EGL context

namespace {

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

}  // namespace

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
    keep_drivers_loaded();
    return true;
  }
  // Sanitized builds only (scripts/sanitize): Mesa unloads its DRI driver at
  // eglTerminate, leaving blocks the driver never frees that LeakSanitizer
  // then reports from an unknown module. Kept loaded, the driver names
  // itself in the report and share/sanitizers/lsan.supp suppresses exactly it.
  static void keep_drivers_loaded() {
#if defined(__SANITIZE_ADDRESS__) || defined(SUFFUSE_ASAN)
    dl_iterate_phdr(
        [](dl_phdr_info* info, std::size_t, void*) {
          const std::string_view path = info->dlpi_name ? info->dlpi_name : "";
          if (path.find("/dri/") != std::string_view::npos)
            dlopen(info->dlpi_name, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);  // a reference never closed
          return 0;
        },
        nullptr);
#endif
  }
  void close() {
    if (display_ == EGL_NO_DISPLAY) return;
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
    if (surface_ != EGL_NO_SURFACE) eglDestroySurface(display_, surface_);
    eglTerminate(display_);
    // The thread's EGL state too (Mesa's, allocated at the first EGL call):
    // otherwise LeakSanitizer reports it once libglvnd has unloaded Mesa.
    eglReleaseThread();
    display_ = EGL_NO_DISPLAY, surface_ = EGL_NO_SURFACE, context_ = EGL_NO_CONTEXT;
  }
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLSurface surface_ = EGL_NO_SURFACE;
  EGLContext context_ = EGL_NO_CONTEXT;
};

namespace {

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

}  // namespace

// ---------------------------------------------------------------- the window

OffscreenRenderWindow::OffscreenRenderWindow(int width, int height)
    : context_(std::make_unique<EglContext>(width, height)) {
  vtkNew<EglRenderWindow> window;
  window->attach(context_.get());
  window->SetSize(width, height);
  window->SetOffScreenRendering(1);
  window->SetMultiSamples(8);
  window->InitializeFromCurrentContext();
  window_ = window;
}

OffscreenRenderWindow::~OffscreenRenderWindow() = default;

}  // namespace suffuse::render
