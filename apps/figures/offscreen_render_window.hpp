// An offscreen OpenGL render window for VTK, without a display.
//
// The Debian VTK 9.1 is built for X only (vtkXOpenGLRenderWindow, no OSMesa or
// EGL window): without $DISPLAY its vtkRenderWindow aborts, offscreen or not.
// So images are drawn into a vtkGenericOpenGLRenderWindow whose OpenGL context
// comes from EGL (Mesa's surfaceless platform, a pbuffer of the image size),
// which needs no X server and no GPU (Mesa falls back to software). suffuse
// plot draws its charts here; other images suffuse renders can too.
#pragma once

#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkSmartPointer.h>

#include <memory>
#include <string>

class vtkOutputWindow;

namespace suffuse::render {

class CollectingOutputWindow;
class EglContext;

// Collects VTK's errors and warnings for its lifetime (they would otherwise go
// to the terminal through its logger), so that a failed rendering becomes a
// suffuse error. Create it before the window, so that it sees its errors too.
class VtkMessages {
 public:
  VtkMessages();
  ~VtkMessages();
  VtkMessages(const VtkMessages&) = delete;
  VtkMessages& operator=(const VtkMessages&) = delete;
  // Throws suffuse::Error with the first error VTK reported, if any.
  void check(const std::string& what) const;
  // Prints VTK's warnings, if any.
  void report_warnings() const;

 private:
  vtkSmartPointer<vtkOutputWindow> previous_;
  vtkSmartPointer<CollectingOutputWindow> window_;
};

// A render window of WIDTH x HEIGHT pixels drawing into its own EGL context,
// initialised and ready to render (8 samples per pixel). Throws suffuse::Error
// when there is no EGL context to be had; VTK's own errors go to VtkMessages.
// Whatever holds the window (a view) must be gone before this is destroyed:
// the window frees its OpenGL objects in the context when it is destroyed.
class OffscreenRenderWindow {
 public:
  OffscreenRenderWindow(int width, int height);
  ~OffscreenRenderWindow();
  OffscreenRenderWindow(const OffscreenRenderWindow&) = delete;
  OffscreenRenderWindow& operator=(const OffscreenRenderWindow&) = delete;

  vtkGenericOpenGLRenderWindow* window() const { return window_; }

 private:
  std::unique_ptr<EglContext> context_;                   // declared first: outlives the window
  vtkSmartPointer<vtkGenericOpenGLRenderWindow> window_;  // an EglRenderWindow on context_
};

}  // namespace suffuse::render
