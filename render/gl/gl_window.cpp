#include "render/gl/gl_window.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <mutex>
#include <stdexcept>

namespace hd::render::gl {

namespace {

std::mutex g_glfw_mutex;  // guards the init count (construction only, never per frame)
int g_glfw_users = 0;
std::string g_last_error;

void on_glfw_error(int code, const char* description) {
  g_last_error = "GLFW error " + std::to_string(code) + ": " + (description ? description : "?");
}

void glfw_acquire() {
  std::lock_guard lock(g_glfw_mutex);
  if (g_glfw_users == 0) {
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
      throw std::runtime_error("GL window: glfwInit failed (is DISPLAY set? run under xvfb-run): " +
                               g_last_error);
    }
  }
  ++g_glfw_users;
}

// GLFW stays initialised until the process exits, even when the last window goes: glfwTerminate
// closes the X display, which makes Mesa dlclose its driver; the driver's own leftovers then have
// no module name and LeakSanitizer can no longer match them to tests/lsan.supp's Mesa entries.
// Re-initialising for the next window would also cost time for nothing.
void glfw_release() {
  std::lock_guard lock(g_glfw_mutex);
  --g_glfw_users;
}

}  // namespace

Window::Window(const WindowOptions& o) {
  glfw_acquire();
  glfwDefaultWindowHints();
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SRGB_CAPABLE, GLFW_FALSE);  // sRGB off: the CPU reference is linear bytes
  glfwWindowHint(GLFW_VISIBLE, o.headless ? GLFW_FALSE : GLFW_TRUE);
  GLFWmonitor* monitor = nullptr;
  int w = o.width, h = o.height;
  if (o.monitor >= 0 && !o.headless) {
    int count = 0;
    GLFWmonitor** monitors = glfwGetMonitors(&count);
    if (o.monitor >= count) {
      glfw_release();
      throw std::runtime_error("GL window: monitor " + std::to_string(o.monitor) + " requested, " +
                               std::to_string(count) + " connected");
    }
    monitor = monitors[o.monitor];
    const GLFWvidmode* mode = glfwGetVideoMode(monitor);
    std::string note;
    if (o.mode_width > 0 && o.mode_height > 0 &&
        (mode->width != o.mode_width || mode->height != o.mode_height)) {
      int n = 0;
      const GLFWvidmode* modes = glfwGetVideoModes(monitor, &n);
      const GLFWvidmode* best = nullptr;
      for (int i = 0; i < n; ++i)
        if (modes[i].width == o.mode_width && modes[i].height == o.mode_height &&
            (!best || modes[i].refreshRate > best->refreshRate))
          best = &modes[i];
      if (best)
        mode = best;
      else
        note = " (" + std::to_string(o.mode_width) + "x" + std::to_string(o.mode_height) +
               " not offered: the current mode)";
    }
    w = mode->width;
    h = mode->height;
    glfwWindowHint(GLFW_REFRESH_RATE, mode->refreshRate);
    const char* name = glfwGetMonitorName(monitor);
    description_ = "monitor " + std::to_string(o.monitor) + " '" + (name ? name : "?") + "' " +
                   std::to_string(w) + "x" + std::to_string(h) + " @ " +
                   std::to_string(mode->refreshRate) + " Hz, fullscreen" + note;
  } else {
    description_ = std::string(o.headless ? "headless " : "window ") + std::to_string(w) + "x" +
                   std::to_string(h);
  }
  window_ = glfwCreateWindow(w, h, o.title.c_str(), monitor, nullptr);
  if (window_ == nullptr) {
    glfw_release();
    throw std::runtime_error("GL window: no OpenGL 3.3 core context could be created: " +
                             g_last_error);
  }
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(o.vsync ? 1 : 0);
}

Window::~Window() {
  glfwDestroyWindow(window_);
  glfw_release();
}

void Window::make_current() {
  glfwMakeContextCurrent(window_);
}
void Window::swap_buffers() {
  glfwSwapBuffers(window_);
}
bool Window::should_close() const {
  return glfwWindowShouldClose(window_) != 0;
}
void Window::poll_events() {
  glfwPollEvents();
}
void Window::framebuffer_size(int* width, int* height) const {
  glfwGetFramebufferSize(window_, width, height);
}

}  // namespace hd::render::gl
