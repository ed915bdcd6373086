// Ctrl-C and SIGTERM as a request rather than a kill: a tool installs the
// handler, and its long loops (bakes, file writes) poll the flag and unwind,
// so that temporaries are removed and no half-written output is left. A
// second signal kills at once.
#pragma once

#include <atomic>
#include <stdexcept>

namespace aal {

// Thrown by throwIfInterrupted().
class Interrupted : public std::runtime_error {
 public:
  Interrupted() : std::runtime_error("interrupted") {}
};

// Sets the flag on the first SIGINT or SIGTERM, then restores the default
// action (the second one kills).
void installInterruptHandler();

// The flag the handler sets (BakeOptions::cancel may point at it).
const std::atomic<bool>& interruptFlag();

// Lowers the flag: for a program that handled one interrupt and goes on
// (and for tests).
void clearInterrupt();

// Throws Interrupted once a signal came; a relaxed load: poll it freely.
inline void throwIfInterrupted() {
  if (interruptFlag().load(std::memory_order_relaxed)) throw Interrupted();
}

}  // namespace aal
