// Progress on stderr for long runs: nothing for the first second, then a bar
// with percentage, elapsed time and ETA, redrawn in place on a terminal and
// every 10% otherwise (so logs stay short). stdout stays clean for data.
#pragma once

#include <chrono>
#include <string>

namespace aal {

class ProgressBar {
 public:
  // `label` starts the line, e.g. "baking". Disabled bars print nothing.
  ProgressBar(std::string label, bool enabled);
  ~ProgressBar();

  // Reports the fraction done in [0, 1]. Call from one thread.
  void update(double fraction);
  // Ends the bar's line (if one was drawn).
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  std::string label_;
  bool enabled_;
  bool interactive_;
  bool drawn_ = false;
  int lastDecile_ = -1;
  Clock::time_point start_ = Clock::now();
  Clock::time_point lastDraw_{};
};

// "1.2 s", "3 min 05 s", "1 h 02 min"
std::string formatDuration(double seconds);

}  // namespace aal
