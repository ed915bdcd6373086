#include "aperture/engine/window/window.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <algorithm>
#include <utility>

#include "aperture/engine/vk/vk_check.h"

namespace aal {

namespace {

constexpr const char* kNoDisplayHint =
    "; aal-view needs a display (set DISPLAY or WAYLAND_DISPLAY, or run it under xvfb-run). "
    "To render images without a window use aal-render.";

std::string lastGlfwError() {
  const char* description = nullptr;
  glfwGetError(&description);
  return description ? description : "unknown GLFW error";
}

Window& owner(GLFWwindow* window) {
  return *static_cast<Window*>(glfwGetWindowUserPointer(window));
}

}  // namespace

Window::Window(int width, int height, const std::string& title) {
  if (!glfwInit()) {
    throw NoDisplayError("cannot open a window: " + lastGlfwError() + kNoDisplayHint);
  }
  if (!glfwVulkanSupported()) {
    glfwTerminate();
    throw NoDisplayError("the window system offers no Vulkan surface" +
                         std::string(kNoDisplayHint));
  }
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
  glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_TRUE);
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window_) {
    const std::string error = lastGlfwError();
    glfwTerminate();
    throw NoDisplayError("cannot create a window: " + error + kNoDisplayHint);
  }
  glfwSetWindowUserPointer(window_, this);
  // Installed before the UI's own callbacks, which chain to these.
  glfwSetScrollCallback(window_, onScroll);
  glfwSetKeyCallback(window_, onKey);
  glfwSetDropCallback(window_, onDrop);
  glfwSetCursorPosCallback(window_, [](GLFWwindow* w, double x, double y) {
    owner(w).cursor_ = {x, y};
    ++owner(w).activity_;
  });
  glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int button, int action, int) {
    if (action == GLFW_PRESS && button >= 0 && button < 8) owner(w).buttonPresses_ |= 1u << button;
    ++owner(w).activity_;
  });
  glfwSetCharCallback(window_, [](GLFWwindow* w, unsigned) { ++owner(w).activity_; });
  glfwSetWindowFocusCallback(window_, [](GLFWwindow* w, int focused) {
    owner(w).focused_ = focused == GLFW_TRUE;
    ++owner(w).activity_;
  });
  glfwSetWindowSizeCallback(window_, [](GLFWwindow* w, int newWidth, int newHeight) {
    owner(w).size_ = {std::max(newWidth, 0), std::max(newHeight, 0)};
  });
  glfwSetWindowRefreshCallback(window_, [](GLFWwindow* w) { ++owner(w).activity_; });
  // The size and the minimised state are kept from their events: asking
  // the X server each frame is a round trip, which waits until it has
  // handled everything queued before it, the last frame's picture included
  // (docs/performance.md, "Where a frame's time goes").
  glfwSetFramebufferSizeCallback(window_, [](GLFWwindow* w, int newWidth, int newHeight) {
    Window& self = owner(w);
    self.framebuffer_ = {static_cast<uint32_t>(std::max(newWidth, 0)),
                         static_cast<uint32_t>(std::max(newHeight, 0))};
    ++self.activity_;
  });
  glfwSetWindowIconifyCallback(window_, [](GLFWwindow* w, int iconified) {
    Window& self = owner(w);
    self.iconified_ = iconified == GLFW_TRUE;
    ++self.activity_;
  });
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  framebuffer_ = {static_cast<uint32_t>(std::max(w, 0)), static_cast<uint32_t>(std::max(h, 0))};
  iconified_ = glfwGetWindowAttrib(window_, GLFW_ICONIFIED) == GLFW_TRUE;
  focused_ = glfwGetWindowAttrib(window_, GLFW_FOCUSED) == GLFW_TRUE;
  glfwGetWindowSize(window_, &w, &h);
  size_ = {std::max(w, 0), std::max(h, 0)};
  glfwGetCursorPos(window_, &cursor_.x, &cursor_.y);
}

Window::~Window() {
  if (window_) glfwDestroyWindow(window_);
  glfwTerminate();
}

std::vector<const char*> Window::requiredInstanceExtensions() {
  uint32_t count = 0;
  const char** names = glfwGetRequiredInstanceExtensions(&count);
  if (!names) throw NoDisplayError("no Vulkan surface extensions" + std::string(kNoDisplayHint));
  return {names, names + count};
}

void Window::pollEvents() {
  glfwPollEvents();
}
void Window::waitEvents(double timeoutS) {
  glfwWaitEventsTimeout(timeoutS);
}

void Window::setCursorCaptured(bool captured) {
  glfwSetInputMode(window_, GLFW_CURSOR, captured ? GLFW_CURSOR_DISABLED : GLFW_CURSOR_NORMAL);
}

bool Window::shouldClose() const {
  return glfwWindowShouldClose(window_);
}
void Window::requestClose() {
  glfwSetWindowShouldClose(window_, GLFW_TRUE);
}
void Window::setTitle(const std::string& title) {
  glfwSetWindowTitle(window_, title.c_str());
}

void Window::setSize(int width, int height) {
  glfwSetWindowSize(window_, width, height);
}
void Window::iconify() {
  glfwIconifyWindow(window_);
}
void Window::restore() {
  glfwRestoreWindow(window_);
}
bool Window::iconified() const {
  return iconified_;
}

VkExtent2D Window::framebufferSize() const {
  return framebuffer_;
}

float Window::contentScale() const {
  float x = 1, y = 1;
  glfwGetWindowContentScale(window_, &x, &y);
  return std::max(1.0f, std::max(x, y));
}

bool Window::keyDown(int glfwKey) const {
  return glfwGetKey(window_, glfwKey) == GLFW_PRESS;
}

bool Window::mouseButtonDown(int glfwButton) const {
  return glfwGetMouseButton(window_, glfwButton) == GLFW_PRESS;
}

glm::dvec2 Window::cursorPosition() const {
  return cursor_;
}

unsigned Window::takeButtonPresses() {
  return std::exchange(buttonPresses_, 0u);
}

double Window::takeWheelSteps() {
  return std::exchange(wheelSteps_, 0.0);
}
std::vector<int> Window::takeKeyPresses() {
  return std::exchange(keyPresses_, {});
}
std::vector<std::string> Window::takeDroppedPaths() {
  return std::exchange(droppedPaths_, {});
}

void Window::onScroll(GLFWwindow* window, double, double y) {
  owner(window).wheelSteps_ += y;
  ++owner(window).activity_;
}

void Window::onKey(GLFWwindow* window, int key, int, int action, int) {
  if (action == GLFW_PRESS) owner(window).keyPresses_.push_back(key);
  ++owner(window).activity_;
}

void Window::onDrop(GLFWwindow* window, int count, const char** paths) {
  for (int i = 0; i < count; ++i) owner(window).droppedPaths_.emplace_back(paths[i]);
  ++owner(window).activity_;
}

bool Window::takeActivity() {
  const bool any = activity_ > 0;
  activity_ = 0;
  return any;
}

Surface::Surface(VkInstance instance, const Window& window) : instance_(instance) {
  AAL_VK_CHECK(glfwCreateWindowSurface(instance, window.handle(), nullptr, &surface_));
}

Surface::~Surface() {
  if (surface_ != VK_NULL_HANDLE) vkDestroySurfaceKHR(instance_, surface_, nullptr);
}

}  // namespace aal
