// aal-render's image sequences (docs/rendering.md, "Image
// sequences and movies"): frame file names, the instants of a --time-range,
// and the MP4 made from the frames by ffmpeg when it is installed.
#pragma once

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/atomic_file.h"
#include "aperture/terrain/light/solar_position.h"

extern char** environ;

namespace aal {

// Frame `index` (0-based) of `count` for the output OUT.ext: OUT-0001.ext, ...
// numbered from 1 with at least four digits (more when count needs them).
inline int sequenceDigits(int count) {
  int digits = 1;
  for (int n = count; n >= 10; n /= 10) ++digits;
  return std::max(4, digits);
}
inline std::string sequenceFramePath(const std::string& output, int index, int count) {
  const std::filesystem::path p(output);
  std::string number = std::to_string(index + 1);
  number = "-" + std::string(size_t(std::max(0, sequenceDigits(count) - int(number.size()))), '0') +
           number;
  return (p.parent_path() / (p.stem().string() + number + p.extension().string())).string();
}
// Whether `name` (a file name, no folder) is one of the `count` frames
// sequenceFramePath gives for `output`: what a sequence writes into the
// output's folder, checked against the inputs before any work.
inline bool isSequenceFrameName(const std::string& output, int count, const std::string& name) {
  const std::filesystem::path p(output);
  const std::string stem = p.stem().string() + "-", extension = p.extension().string();
  const size_t digits = static_cast<size_t>(sequenceDigits(count));
  if (name.size() != stem.size() + digits + extension.size() || name.rfind(stem, 0) != 0 ||
      name.compare(name.size() - extension.size(), extension.size(), extension) != 0) {
    return false;
  }
  long index = 0;
  for (size_t i = stem.size(); i < stem.size() + digits; ++i) {
    if (name[i] < '0' || name[i] > '9') return false;
    index = index * 10 + (name[i] - '0');
  }
  return index >= 1 && index <= count;
}
// ffmpeg's input pattern for those frames (OUT-%04d.ext).
inline std::string sequencePattern(const std::string& output, int count) {
  const std::filesystem::path p(output);
  return (p.parent_path() / (p.stem().string() + "-%0" + std::to_string(sequenceDigits(count)) +
                             "d" + p.extension().string()))
      .string();
}

// The instant of frame `index` of `count` spread evenly from `start` to `end`
// (both included; one frame is `start`).
inline UtcTime sequenceTime(const UtcTime& start, const UtcTime& end, int index, int count) {
  if (count <= 1) return start;
  return addSeconds(start, secondsBetween(start, end) * index / (count - 1));
}

// The ffmpeg executable: $AAL_FFMPEG when set (empty: none, for tests), else
// the first `ffmpeg` on $PATH; nullopt when there is none.
inline std::optional<std::string> findFfmpeg() {
  if (const char* forced = std::getenv("AAL_FFMPEG")) {
    if (*forced && access(forced, X_OK) == 0) return std::string(forced);
    return std::nullopt;
  }
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "";
  size_t begin = 0;
  while (begin <= dirs.size()) {
    const size_t end = std::min(dirs.find(':', begin), dirs.size());
    const std::string dir = dirs.substr(begin, end - begin);
    const std::string candidate = (dir.empty() ? std::string(".") : dir) + "/ffmpeg";
    if (access(candidate.c_str(), X_OK) == 0) return candidate;
    begin = end + 1;
  }
  return std::nullopt;
}

// Encodes the PNG frames `pattern` at `fps` into `mp4` (H.264, yuv420p,
// dimensions padded to even numbers as the codec needs) with `ffmpeg`,
// through a temporary file renamed into place (AtomicOutput): a failed
// encoding leaves an earlier `mp4` as it was. Throws std::runtime_error when
// ffmpeg fails (its messages went to stderr).
inline void encodeMp4(const std::string& ffmpeg, const std::string& pattern, double fps,
                      const std::string& mp4) {
  AtomicOutput output(mp4);  // checkOutputWritable: a file, not a device
  const std::string rate = std::to_string(fps);
  const std::string temporary = output.temporaryPath().string();
  std::vector<std::string> args = {
      ffmpeg,       "-y",      "-loglevel", "error",   "-framerate",
      rate,         "-i",      pattern,     "-vf",     "pad=ceil(iw/2)*2:ceil(ih/2)*2",
      "-c:v",       "libx264", "-pix_fmt",  "yuv420p", "-movflags",
      "+faststart", temporary};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, ffmpeg.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
    throw std::runtime_error("could not start " + ffmpeg);
  }
  int status = 0;
  if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw std::runtime_error(ffmpeg + " failed to encode " + pattern + " into " + mp4);
  }
  output.commit();
}

}  // namespace aal
