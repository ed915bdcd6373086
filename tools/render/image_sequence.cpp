#include "aperture/tools/render/image_sequence.h"

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "aperture/engine/screenshot.h"
#include "aperture/engine/supersampling.h"
#include "aperture/preprocess/progress_reporter.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/interrupt.h"
#include "aperture/terrain/light/lighting_defaults.h"
#include "aperture/terrain/light/sky_lighting.h"
#include "aperture/tools/render/still_image.h"
#include "aperture/tools/render_sequence.h"
#include "aperture/tools/tool_main.h"

namespace aal {
namespace {

// --time-range START END: two instants, the end after the start.
void parseTimeRange(const RenderOptions& o, ImageSequence& s) {
  if (!o.sun.time.empty() || o.sun.azimuthDeg) {
    throw InputError(
        "--time-range sets the sun: leave out --time, --sun-azimuth and --sun-elevation");
  }
  s.start = parseIso8601Utc(o.timeRange[0]);
  s.end = parseIso8601Utc(o.timeRange[1]);
  for (int i = 0; i < 2; ++i) {
    if (!(i == 0 ? s.start : s.end)) {
      throw InputError("--time-range takes two ISO 8601 times, e.g. 2024-06-21T10:00Z, got '" +
                       o.timeRange[i] + "'");
    }
  }
  if (!(secondsBetween(*s.start, *s.end) > 0)) {
    throw InputError("--time-range END (" + o.timeRange[1] + ") must come after START (" +
                     o.timeRange[0] + ")");
  }
}

}  // namespace

std::optional<ImageSequence> imageSequenceOf(const RenderOptions& o, bool reference) {
  const bool wanted = !o.cameraPath.empty() || !o.timeRange.empty();
  if (!wanted) {
    if (o.frames) throw InputError("--frames needs --camera-path FILE or --time-range");
    if (o.temporal != "auto") {
      throw InputError("--temporal is for image sequences (--camera-path, --time-range)");
    }
    return std::nullopt;
  }
  if (!o.frames) {
    throw InputError("--camera-path and --time-range need --frames N (how many images)");
  }
  if (*o.frames < 1 || *o.frames > 1'000'000) {
    throw InputError("--frames must be in [1, 1000000], got " + std::to_string(*o.frames));
  }
  // --compare takes a camera path as the pan its shimmer is measured along.
  if (reference || (!o.compare.empty() && !o.timeRange.empty())) {
    throw InputError(std::string(reference ? "an image sequence (--camera-path, --time-range)"
                                           : "--time-range") +
                     " is for -o images of the GPU renderer, not " +
                     (reference ? "--mode reference" : "--compare"));
  }
  if (!o.compare.empty() && *o.frames < 3) {
    throw InputError(
        "--compare with --camera-path measures the shimmer along it: give "
        "--frames 3 or more (a second difference in time needs three), got " +
        std::to_string(*o.frames));
  }
  ImageSequence s;
  s.frames = *o.frames;
  if (!o.cameraPath.empty()) {
    if (!o.camera.position.empty() || !o.camera.lookAt.empty()) {
      throw InputError("--camera-path sets the camera: leave out --camera and --look-at");
    }
  }
  if (!o.timeRange.empty()) parseTimeRange(o, s);
  // The history follows the camera's motion, not the sun's: a time-lapse
  // would show its shadows trailing.
  s.temporal = o.temporal == "on" || (o.temporal == "auto" && o.timeRange.empty());
  return s;
}

void setSequenceFrame(const RenderOptions& o, const ImageSequence& seq, const Heightfield& field,
                      int i, FrameSettings& settings) {
  if (seq.path) settings.camera = seq.path->at(seq.path->frameTime(i, seq.frames));
  if (seq.start) {
    const GeoPlace place = defaultSunPlace(field);
    const double lat = o.sun.latitudeDeg.value_or(place.latitudeDeg),
                 lon = o.sun.longitudeDeg.value_or(place.longitudeDeg);
    const UtcTime t = sequenceTime(*seq.start, *seq.end, i, seq.frames);
    const SolarPosition sun = solarPosition(t, lat, lon);
    setSunAndSky(settings.lighting, sun.azimuthDeg, sun.elevationDeg, o.turbidity,
                 sun.sunDistanceAu);
  }
}

std::string moviePath(const RenderOptions& o) {
  if (wantsLinearOutput(o.output)) return {};
  return std::filesystem::path(o.output).replace_extension(".mp4").string();
}

OutputFamily sequenceFrameFiles(const std::string& output, int count) {
  const std::string folder = std::filesystem::path(output).parent_path().string();
  const auto name = [&](int i) {
    return std::filesystem::path(sequenceFramePath(output, i, count)).filename().string();
  };
  return {"-o", output, folder.empty() ? "." : folder,
          "the frames " + name(0) + (count > 1 ? " .. " + name(count - 1) : ""),
          [output, count](const std::string& file) {
            return isSequenceFrameName(output, count, file);
          }};
}

namespace {

// The frames' MP4 when ffmpeg is installed; a note when it is not.
void encodeMovie(const RenderOptions& o, const ImageSequence& seq) {
  const std::optional<std::string> ffmpeg = findFfmpeg();
  const std::string mp4 = moviePath(o);
  if (!ffmpeg) {
    if (!o.report.quiet) {
      std::fprintf(stderr, "aal-render: ffmpeg not found (Debian: apt-get install ffmpeg): no %s\n",
                   mp4.c_str());
    }
    return;
  }
  encodeMp4(*ffmpeg, sequencePattern(o.output, seq.frames), o.fps, mp4);
  if (!o.report.quiet) std::fprintf(stderr, "aal-render: wrote %s\n", mp4.c_str());
}

}  // namespace

int renderSequence(const RenderOptions& o, const ImageSequence& seq, const Heightfield& field,
                   const TerrainScene& scene, TerrainRenderer& renderer, FrameSettings settings) {
  ProgressReporter bar(o.report.style(), "rendering",
                       "rendering " + std::to_string(seq.frames) + " frames",
                       static_cast<uint64_t>(seq.frames));
  const auto start = std::chrono::steady_clock::now();
  if (seq.temporal) {
    FrameSettings first = settings;
    setSequenceFrame(o, seq, field, 0, first);
    startAccumulation(renderer, scene, first, o.supersample);
  }
  for (int i = 0; i < seq.frames; ++i) {
    setSequenceFrame(o, seq, field, i, settings);
    throwIfInterrupted();
    const FrameResult frame = renderOutputFrame(o, scene, renderer, settings, seq.temporal);
    writeFrame(sequenceFramePath(o.output, i, seq.frames), frame);
    bar.updateDone(static_cast<uint64_t>(i + 1));
  }
  bar.finish();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string first = sequenceFramePath(o.output, 0, seq.frames),
                    last = sequenceFramePath(o.output, seq.frames - 1, seq.frames);
  if (!o.report.quiet) {
    std::fprintf(stderr, "aal-render: %d frames in %.1f s (%.0f ms each): %s .. %s\n", seq.frames,
                 seconds, 1e3 * seconds / seq.frames, first.c_str(), last.c_str());
  }
  if (wantsLinearOutput(o.output)) return kExitOk;  // EXR frames: no movie
  encodeMovie(o, seq);
  return kExitOk;
}

}  // namespace aal
