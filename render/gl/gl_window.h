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
  /// Fullscreen: the video mode to ask for (an HMD's native panel mode), the highest refresh
  /// rate of that size; 0 or no such mode: the monitor's current mode.
  int mode_width = 0;
  int mode_height = 0;
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
  /// What it is on, for the start report: "monitor 1 'HDK' 1920x1080 @ 60 Hz, fullscreen" (with
  /// a note when the requested mode was not offered), "window 1600x600" or "headless 1600x600".
  const std::string& description() const { return description_; }

 private:
  GLFWwindow* window_ = nullptr;
  std::string description_;
};

}  // namespace hd::render::gl
