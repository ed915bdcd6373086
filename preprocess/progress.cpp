#include "aperture/preprocess/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace aal {

std::string formatDuration(double seconds) {
  char text[32];
  if (seconds < 60) {
    std::snprintf(text, sizeof text, "%.1f s", seconds);
  } else if (seconds < 3600) {
    std::snprintf(text, sizeof text, "%d min %02d s", int(seconds) / 60, int(seconds) % 60);
  } else {
    std::snprintf(text, sizeof text, "%d h %02d min", int(seconds) / 3600,
                  (int(seconds) % 3600) / 60);
  }
  return text;
}

ProgressBar::ProgressBar(std::string label, bool enabled)
    : label_(std::move(label)), enabled_(enabled), interactive_(::isatty(STDERR_FILENO) == 1) {}

ProgressBar::~ProgressBar() {
  finish();
}

void ProgressBar::update(double fraction) {
  if (!enabled_) return;
  fraction = std::clamp(fraction, 0.0, 1.0);
  const Clock::time_point now = Clock::now();
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  if (elapsed < 1.0) return;  // short runs stay quiet
  const double eta = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0;
  const int percent = static_cast<int>(std::floor(100 * fraction));
  if (interactive_) {
    if (drawn_ && now - lastDraw_ < std::chrono::milliseconds(100) && fraction < 1) return;
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(kWidth * fraction);
    std::string bar(filled, '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "\r%s [%s] %3d%%  %s elapsed, %s left   ", label_.c_str(), bar.c_str(),
                 percent, formatDuration(elapsed).c_str(), formatDuration(eta).c_str());
  } else {
    const int decile = percent / 10;
    if (decile == lastDecile_) return;
    lastDecile_ = decile;
    std::fprintf(stderr, "%s: %3d%%  %s elapsed, %s left\n", label_.c_str(), percent,
                 formatDuration(elapsed).c_str(), formatDuration(eta).c_str());
  }
  std::fflush(stderr);
  drawn_ = true;
  lastDraw_ = now;
}

void ProgressBar::finish() {
  if (drawn_ && interactive_) std::fputc('\n', stderr);
  drawn_ = false;
}

}  // namespace aal
