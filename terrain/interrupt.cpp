#include "aperture/terrain/interrupt.h"

#include <semaphore.h>
#include <signal.h>
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

// The signals that were ignored when the process started (nohup ignores
// SIGHUP, a shell without job control SIGINT for a background command):
// they stay ignored, as the caller asked, and only the others are handled.
std::atomic<unsigned> gIgnoredAtStart{0};

bool ignoredAtStart(int signal) {
  return (gIgnoredAtStart.load() >> signal) & 1u;
}

extern "C" void onInterrupt(int signal) {
  gSignal.store(signal);
  gInterrupted.store(true);
  for (int s : kSignals) {
    if (!ignoredAtStart(s)) std::signal(s, SIG_DFL);  // any second signal kills
  }
  sem_post(&gWake);  // async-signal-safe
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
    unsigned ignored = 0;
    for (int s : kSignals) {
      struct sigaction current {};
      if (sigaction(s, nullptr, &current) == 0 && current.sa_handler == SIG_IGN) {
        ignored |= 1u << s;
      }
    }
    gIgnoredAtStart.store(ignored);
    sem_init(&gWake, 0, 0);
    std::thread(watchdog).detach();
  });
  for (int s : kSignals) {
    if (!ignoredAtStart(s)) std::signal(s, onInterrupt);
  }
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
