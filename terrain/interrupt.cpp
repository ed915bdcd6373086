#include "aperture/terrain/interrupt.h"

#include <csignal>

namespace aal {

namespace {

std::atomic<bool> gInterrupted{false};

extern "C" void onInterrupt(int signal) {
  gInterrupted.store(true);
  std::signal(signal, SIG_DFL);
}

}  // namespace

void installInterruptHandler() {
  std::signal(SIGINT, onInterrupt);
  std::signal(SIGTERM, onInterrupt);
}

void clearInterrupt() {
  gInterrupted.store(false);
}

const std::atomic<bool>& interruptFlag() {
  return gInterrupted;
}

}  // namespace aal
