#pragma once
// The GLFW window (and its OpenGL 3.3 core context) the GL compositor draws into.

#include <string>

struct GLFWwindow;

namespace hd::render::gl {

struct WindowOptions {
  int width = 800;  ///< windowed / headless size (fullscreen uses the monitor's mode)
  int height = 600;
  bool headless = false;  ///< an invisible window: the context only, pictures are read back
  int monitor = -1;       ///< >= 0: fullscreen on this monitor (e.g. the HMD), else windowed
  bool vsync = true;      ///< swap interval 1 (Xvfb does not throttle; the loop paces itself)
  std::string title = "hybrid-station";
};

/// Initialises GLFW once per process (see gl_window.cpp) and owns one window with a current 3.3
/// core context. Construction throws std::runtime_error naming what failed (no display, no 3.3 core
/// context, monitor index out of range); after that nothing throws.
class Window {
 public:
  explicit Window(const WindowOptions& options);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  void make_current();
  void swap_buffers();
  bool should_close() const;
  void poll_events();
  /// The default framebuffer's size in pixels.
  void framebuffer_size(int* width, int* height) const;
  GLFWwindow* handle() const { return window_; }

 private:
  GLFWwindow* window_ = nullptr;
};

}  // namespace hd::render::gl
