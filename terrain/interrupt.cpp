#include "aperture/terrain/interrupt.h"

#include <semaphore.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <thread>

namespace aal {

namespace {

constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP};

std::atomic<bool> gInterrupted{false};
std::atomic<int> gSignal{0};
std::atomic<void (*)()> gCleanup{nullptr};
sem_t gWake;

extern "C" void onInterrupt(int signal) {
  gSignal.store(signal);
  gInterrupted.store(true);
  for (int s : kSignals) std::signal(s, SIG_DFL);  // any second signal kills
  sem_post(&gWake);                                // async-signal-safe
}

// Waits for a signal, gives the tool kInterruptGraceSeconds to unwind, and
// ends it if it has not (a read blocked in a library, a loop that does not
// poll): the user asked it to stop, and it stops.
void watchdog() {
  for (;;) {
    while (sem_wait(&gWake) != 0) {
    }
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::duration<double>(kInterruptGraceSeconds);
    while (gInterrupted.load() && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (!gInterrupted.load()) continue;  // cleared: the program goes on
    if (void (*cleanup)() = gCleanup.load()) cleanup();
    static const char kMessage[] = "interrupted: stopped\n";
    [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
    std::_Exit(128 + gSignal.load());
  }
}

}  // namespace

void installInterruptHandler() {
  static std::once_flag started;
  std::call_once(started, [] {
    sem_init(&gWake, 0, 0);
    std::thread(watchdog).detach();
  });
  for (int s : kSignals) std::signal(s, onInterrupt);
}

void clearInterrupt() {
  gInterrupted.store(false);
}

void setInterruptCleanup(void (*cleanup)()) {
  gCleanup.store(cleanup);
}

void runInterruptCleanup() {
  if (void (*cleanup)() = gCleanup.load()) cleanup();
}

const std::atomic<bool>& interruptFlag() {
  return gInterrupted;
}

}  // namespace aal
