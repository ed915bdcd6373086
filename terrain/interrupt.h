// Ctrl-C, SIGTERM and SIGHUP as a request rather than a kill: a tool installs
// the handler, and its long loops (bakes, DEM reads, file writes) poll the
// flag and unwind, so that temporaries are removed and no half-written
// output is left. Whatever the tool is doing, it ends within a second of the
// first signal: a watchdog ends the process then (after removing the
// temporaries of the outputs being written), and a second signal of any kind
// kills at once.
#pragma once

#include <atomic>
#include <stdexcept>

namespace aal {

// Thrown by throwIfInterrupted().
class Interrupted : public std::runtime_error {
 public:
  Interrupted() : std::runtime_error("interrupted") {}
};

// How long the tool may take to unwind after the first signal before the
// watchdog ends it (exit status 128 + the signal, as a kill would give).
constexpr double kInterruptGraceSeconds = 0.8;

// Sets the flag on the first SIGINT, SIGTERM or SIGHUP, restores the default
// action of all three (the second signal kills), and starts the watchdog.
// A signal ignored when the process started stays ignored (nohup's SIGHUP,
// SIGINT for a background command of a non-interactive shell).
void installInterruptHandler();

// The flag the handler sets (BakeOptions::cancel may point at it).
const std::atomic<bool>& interruptFlag();

// Lowers the flag and stands the watchdog down: for a program that handled
// one interrupt and goes on (and for tests).
void clearInterrupt();

// Called by the watchdog just before it ends the process (AtomicOutput
// removes its temporaries there). One function; async-signal-safety is not
// needed (the watchdog is a thread), but it must not wait on a lock the
// interrupted thread may hold for long.
void setInterruptCleanup(void (*cleanup)());

// Runs that function now, for a path that must end the process at once
// without unwinding (a library's fatal error): no temporary is left behind.
void runInterruptCleanup();

// Throws Interrupted once a signal came; a relaxed load: poll it freely.
inline void throwIfInterrupted() {
  if (interruptFlag().load(std::memory_order_relaxed)) throw Interrupted();
}

}  // namespace aal
