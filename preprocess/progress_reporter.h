// Progress of a tool's long stages in the form its caller asked for
// (--progress, tools/options/output_options.h; docs/cli.md): a bar for a
// person (progress.h, on stderr), GDAL's terminal progress or JSON lines for
// a script or a GUI (on stdout), or nothing.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

namespace aal {

class ProgressBar;

enum class ProgressStyle {
  Bar,   // progress.h's bar on stderr, after the first second
  Gdal,  // "0...10...20...30...40...50...60...70...80...90...100 - done." on stdout
  Json,  // {"stage":"baking","done":N,"total":M,"seconds":S}, one object a line, on stdout
  None,
};

// "bar, gdal, json, none": the names --progress takes, in that order.
inline constexpr const char* kProgressStyleNames[] = {"bar", "gdal", "json", "none"};

// The style named `name` (one of kProgressStyleNames), else nullopt.
std::optional<ProgressStyle> parseProgressStyle(std::string_view name);

// The total of a stage that reports fractions: thousandths.
inline constexpr uint64_t kFractionTotal = 1000;

// One stage of a tool's work. `stage` is its stable name for scripts
// ("baking", "shading", "tracing", "rendering"; docs/cli.md); `label` is the
// bar's words for a person. Json writes the stage's first line (done 0) when
// constructed, then at most one line per 100 ms, and always its last line
// (finish, or when done reaches total); every line is flushed at once. Gdal
// writes "0" when constructed and a dot or a number for every 2.5 % after,
// ending "100 - done." and a newline, as GDAL's GDALTermProgress does.
// `done` never goes back: a smaller value than one reported is held at it.
// Safe to call from several threads.
class ProgressReporter {
 public:
  // `total`: the stage's units of work (frames, tiles); by default
  // thousandths, for a stage that reports a fraction.
  ProgressReporter(ProgressStyle style, std::string stage, std::string label,
                   uint64_t total = kFractionTotal);
  ~ProgressReporter();
  ProgressReporter(const ProgressReporter&) = delete;
  ProgressReporter& operator=(const ProgressReporter&) = delete;

  // `done` of the stage's total units of work.
  void updateDone(uint64_t done);
  // A fraction in [0, 1] of the stage, as that share of its total.
  void update(double fraction);
  // Ends the stage: Json's last line if it was held back, the end of Bar's
  // and Gdal's line. A stage cut short (interrupted) ends where it stood.
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  void writeJson(Clock::time_point now);
  void writeGdalTicks(int ticks);

  ProgressStyle style_;
  std::string stage_;
  std::unique_ptr<ProgressBar> bar_;
  std::mutex mutex_;
  Clock::time_point start_ = Clock::now();
  Clock::time_point lastJson_{};
  uint64_t done_ = 0, total_;
  bool jsonPending_ = false;  // a state not yet written (throttled)
  int gdalTicks_ = 0;         // of 40, each 2.5 %
  bool finished_ = false;
};

}  // namespace aal
