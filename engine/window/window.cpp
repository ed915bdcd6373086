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
  glfwSetCursorPosCallback(window_, [](GLFWwindow* w, double, double) { ++owner(w).activity_; });
  glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int, int, int) { ++owner(w).activity_; });
  glfwSetCharCallback(window_, [](GLFWwindow* w, unsigned) { ++owner(w).activity_; });
  glfwSetWindowFocusCallback(window_, [](GLFWwindow* w, int) { ++owner(w).activity_; });
  glfwSetWindowRefreshCallback(window_, [](GLFWwindow* w) { ++owner(w).activity_; });
  glfwSetFramebufferSizeCallback(window_, [](GLFWwindow* w, int, int) { ++owner(w).activity_; });
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
  return glfwGetWindowAttrib(window_, GLFW_ICONIFIED) == GLFW_TRUE;
}

VkExtent2D Window::framebufferSize() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  return {static_cast<uint32_t>(std::max(w, 0)), static_cast<uint32_t>(std::max(h, 0))};
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
  glm::dvec2 p{0.0};
  glfwGetCursorPos(window_, &p.x, &p.y);
  return p;
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
