#include "aperture/preprocess/progress_reporter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "aperture/preprocess/progress.h"

namespace aal {

namespace {

// GDAL's terminal progress: 40 ticks of 2.5 %, every fourth a number.
constexpr int kGdalTicks = 40;
constexpr auto kJsonInterval = std::chrono::milliseconds(100);

}  // namespace

std::optional<ProgressStyle> parseProgressStyle(std::string_view name) {
  if (name == "bar") return ProgressStyle::Bar;
  if (name == "gdal") return ProgressStyle::Gdal;
  if (name == "json") return ProgressStyle::Json;
  if (name == "none") return ProgressStyle::None;
  return std::nullopt;
}

ProgressReporter::ProgressReporter(ProgressStyle style, std::string stage, std::string label,
                                   uint64_t total)
    : style_(style), stage_(std::move(stage)), total_(std::max<uint64_t>(total, 1)) {
  switch (style_) {
    case ProgressStyle::Bar: bar_ = std::make_unique<ProgressBar>(std::move(label), true); break;
    case ProgressStyle::Gdal:
      std::fputs("0", stdout);
      std::fflush(stdout);
      break;
    case ProgressStyle::Json: writeJson(start_); break;
    case ProgressStyle::None: break;
  }
}

ProgressReporter::~ProgressReporter() {
  finish();
}

void ProgressReporter::updateDone(uint64_t done) {
  if (style_ == ProgressStyle::None) return;
  const std::lock_guard lock(mutex_);
  if (finished_) return;
  // Held where it stood: a later report of less (a tiled bake's 0 when it
  // starts its tiles) would read as going back.
  done = std::clamp(done, done_, total_);
  // The bar redraws its elapsed time; the others only say news.
  if (done == done_ && style_ != ProgressStyle::Bar) return;
  done_ = done;
  const double fraction = double(done_) / double(total_);
  switch (style_) {
    case ProgressStyle::Bar: bar_->update(fraction); break;
    case ProgressStyle::Gdal:
      writeGdalTicks(static_cast<int>(std::floor(fraction * kGdalTicks)));
      break;
    case ProgressStyle::Json: {
      const Clock::time_point now = Clock::now();
      jsonPending_ = true;
      if (done_ == total_ || now - lastJson_ >= kJsonInterval) writeJson(now);
      break;
    }
    case ProgressStyle::None: break;
  }
}

void ProgressReporter::update(double fraction) {
  if (!(fraction >= 0)) fraction = 0;  // NaN too
  fraction = std::min(fraction, 1.0);
  updateDone(static_cast<uint64_t>(std::floor(fraction * double(total_))));
}

void ProgressReporter::finish() {
  const std::lock_guard lock(mutex_);
  if (finished_) return;
  finished_ = true;
  switch (style_) {
    case ProgressStyle::Bar: bar_->finish(); break;
    case ProgressStyle::Gdal:
      // A stage cut short ends its line where it stood.
      if (gdalTicks_ < kGdalTicks) {
        std::fputc('\n', stdout);
        std::fflush(stdout);
      }
      break;
    case ProgressStyle::Json:
      if (jsonPending_) writeJson(Clock::now());
      break;
    case ProgressStyle::None: break;
  }
}

void ProgressReporter::writeJson(Clock::time_point now) {
  const double seconds = std::chrono::duration<double>(now - start_).count();
  // The stage names are ours (plain words): nothing in them needs escaping.
  std::fprintf(stdout, "{\"stage\":\"%s\",\"done\":%llu,\"total\":%llu,\"seconds\":%.3f}\n",
               stage_.c_str(), static_cast<unsigned long long>(done_),
               static_cast<unsigned long long>(total_), seconds);
  std::fflush(stdout);
  lastJson_ = now;
  jsonPending_ = false;
}

void ProgressReporter::writeGdalTicks(int ticks) {
  if (ticks <= gdalTicks_) return;
  for (int tick = gdalTicks_ + 1; tick <= ticks; ++tick) {
    if (tick % 4 == 0) {
      std::fprintf(stdout, "%d", tick / 4 * 10);
    } else {
      std::fputc('.', stdout);
    }
  }
  gdalTicks_ = ticks;
  if (gdalTicks_ == kGdalTicks) std::fputs(" - done.\n", stdout);
  std::fflush(stdout);
}

}  // namespace aal
