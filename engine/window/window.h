// A desktop window (GLFW) with a Vulkan surface, and its input: keys and
// mouse polled per frame, wheel steps, key presses and dropped files queued
// by callbacks until the frame takes them.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>
#include <glm/vec2.hpp>

struct GLFWwindow;

namespace aal {

// No window can be opened (no display, or no Vulkan-capable window system).
// The message tells the user to render headless with aal-render instead.
class NoDisplayError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Window {
 public:
  // Opens a resizable window of `width` x `height` screen coordinates.
  // Throws NoDisplayError when GLFW cannot start (no DISPLAY/WAYLAND_DISPLAY,
  // or the display is unreachable) or has no Vulkan support.
  Window(int width, int height, const std::string& title);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  GLFWwindow* handle() const { return window_; }
  // Instance extensions needed for this window's surface.
  static std::vector<const char*> requiredInstanceExtensions();

  void pollEvents();
  // Blocks until an event arrives or `timeoutS` passes (used while minimised).
  void waitEvents(double timeoutS);
  // Hides the cursor and reports unbounded movement (while looking around).
  void setCursorCaptured(bool captured);
  bool shouldClose() const;
  void requestClose();
  void setTitle(const std::string& title);

  // Scripted window changes (aal-view's test hooks), as if the user had
  // made them; a window manager may adjust or ignore them, and without one
  // (a bare X server such as Xvfb) iconifying does nothing.
  void setSize(int width, int height);
  void iconify();
  void restore();
  // True while the window is minimised (iconified). X11 keeps the size of an
  // iconified window, so a 0 x 0 framebuffer alone does not tell.
  bool iconified() const;

  // Size of the drawable area in pixels; 0 x 0 while minimised. On high-DPI
  // screens it differs from the window size in screen coordinates.
  VkExtent2D framebufferSize() const;
  // The window's size in screen coordinates (the panel's units).
  glm::ivec2 size() const { return size_; }
  bool focused() const { return focused_; }
  // Monitor content scale (1 on a standard-DPI screen): UI sizes scale by it.
  float contentScale() const;

  bool keyDown(int glfwKey) const;
  bool mouseButtonDown(int glfwButton) const;
  // Where the cursor was last reported (screen coordinates; while captured,
  // unbounded). Kept from the events: the window's state is read without
  // asking the X server (framebufferSize).
  glm::dvec2 cursorPosition() const;
  // Bit b: mouse button b was pressed since the last call (a click shorter
  // than a frame still counts).
  unsigned takeButtonPresses();
  // Input queued since the last call of each.
  double takeWheelSteps();
  std::vector<int> takeKeyPresses();
  std::vector<std::string> takeDroppedPaths();
  // Whether any input or window event (keys, mouse, wheel, characters,
  // focus, resizing, exposure, drops) arrived since the last call: an idle
  // viewer draws nothing until one does.
  bool takeActivity();

 private:
  static void onScroll(GLFWwindow* window, double x, double y);
  static void onKey(GLFWwindow* window, int key, int scancode, int action, int mods);
  static void onDrop(GLFWwindow* window, int count, const char** paths);

  GLFWwindow* window_ = nullptr;
  double wheelSteps_ = 0;
  std::vector<int> keyPresses_;
  std::vector<std::string> droppedPaths_;
  unsigned activity_ = 0;
  VkExtent2D framebuffer_{0, 0};  // from the size events
  bool iconified_ = false;        // from the iconify events
  glm::ivec2 size_{0};            // screen coordinates
  bool focused_ = false;
  glm::dvec2 cursor_{0.0};
  unsigned buttonPresses_ = 0;
};

// A VkSurfaceKHR for a window, destroyed with its instance still alive.
class Surface {
 public:
  Surface(VkInstance instance, const Window& window);
  ~Surface();
  Surface(const Surface&) = delete;
  Surface& operator=(const Surface&) = delete;

  VkSurfaceKHR handle() const { return surface_; }

 private:
  VkInstance instance_ = VK_NULL_HANDLE;
  VkSurfaceKHR surface_ = VK_NULL_HANDLE;
};

}  // namespace aal
