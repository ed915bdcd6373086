#include "aperture/tools/mode_comparison.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "aperture/engine/screenshot.h"
#include "aperture/engine/supersampling.h"
#include "aperture/terrain/io/atomic_file.h"
#include "aperture/terrain/light/atmosphere.h"
#include "aperture/terrain/light/tone_map.h"
#include "aperture/terrain/reference/shimmer.h"

namespace aal {

namespace {

std::vector<glm::vec3> linearRgb(const FrameResult& frame) {
  std::vector<glm::vec3> rgb(size_t(frame.width) * frame.height);
  for (size_t i = 0; i < rgb.size(); ++i) {
    rgb[i] = {frame.linear[4 * i], frame.linear[4 * i + 1], frame.linear[4 * i + 2]};
  }
  return rgb;
}

FrameResult imageFrame(uint32_t width, uint32_t height) {
  FrameResult f;
  f.width = width;
  f.height = height;
  f.display.assign(size_t(width) * height * 4, 0);
  f.linear.assign(size_t(width) * height * 4, 0.0f);
  return f;
}

// A mode's frame settings: the reference traces the DEM's own surface, so
// the GPU draws the finest mesh the budget allows and the errors are the
// shading's; the ground's albedo is the reference's.
FrameSettings modeSettings(const FrameSettings& settings, const ComparedMode& m,
                           const ComparisonOptions& options) {
  FrameSettings s = settings;
  s.lod.maxErrorPixels = s.lod.maxErrorPixels > 0
                             ? std::min(s.lod.maxErrorPixels, kComparisonLodErrorPixels)
                             : kComparisonLodErrorPixels;
  s.mode = m.mode;
  s.obscurance.enabled = m.obscurance;
  s.albedoValue = options.albedo;
  return s;
}

// The reference's size: the renderer's, less its supersampling.
uint32_t outputWidth(const TerrainRenderer& renderer, const ComparisonOptions& options) {
  return renderer.width() / std::max(options.supersample, 1u);
}
uint32_t outputHeight(const TerrainRenderer& renderer, const ComparisonOptions& options) {
  return renderer.height() / std::max(options.supersample, 1u);
}

// A mode's frame at the reference's size, linear values included.
// `accumulate`: a frame of the pan's accumulated sequence.
FrameResult modeFrame(TerrainRenderer& renderer, const TerrainScene& scene, const FrameSettings& s,
                      const ComparisonOptions& options, bool accumulate = false) {
  return renderSupersampled(renderer, scene, s, options.supersample, true, accumulate);
}

}  // namespace

std::vector<ComparedMode> defaultComparedModes(const FrameSettings& settings) {
  const bool w = settings.obscurance.enabled;
  std::vector<ComparedMode> modes = {{"approx", ShadingMode::Approx, w},
                                     {"exact", ShadingMode::Exact, w}};
  if (w) modes.push_back({"approx-without-w", ShadingMode::Approx, false});
  modes.push_back({"baseline-lambert", ShadingMode::BaselineLambert, false});
  modes.push_back({"baseline-ao", ShadingMode::BaselineAo, false});
  return modes;
}

ReferenceSettings referenceSettingsFor(const FrameSettings& settings, uint32_t width,
                                       uint32_t height, const ComparisonOptions& options) {
  ReferenceSettings r;
  r.camera = settings.camera;
  r.width = width;
  r.height = height;
  r.lighting = settings.lighting;
  r.albedo = options.albedo;
  r.sunRays = options.sunRays;
  r.skyRays = options.skyRays;
  r.subpixels = options.subpixels;
  r.interreflection = options.interreflection;
  r.skyBackground = true;
  return r;
}

FrameResult referenceFrame(const ReferenceImage& image, float exposure) {
  FrameResult frame = imageFrame(image.width, image.height);
  for (size_t i = 0; i < image.radiance.size(); ++i) {
    const glm::vec3 l = image.radiance[i];
    const glm::vec3 d = toneMap(l, exposure);
    for (int k = 0; k < 3; ++k) {
      frame.linear[4 * i + k] = l[k];
      frame.display[4 * i + k] = static_cast<uint8_t>(std::lround(255.0f * d[k]));
    }
    frame.linear[4 * i + 3] = 1.0f;
    frame.display[4 * i + 3] = 255;
  }
  return frame;
}

Comparison compareModes(TerrainRenderer& renderer, const TerrainScene& scene,
                        const Heightfield& field, const FrameSettings& settings,
                        const std::vector<ComparedMode>& modes, const ComparisonOptions& options,
                        const std::function<void(double)>& progress) {
  Comparison c;
  const auto start = std::chrono::steady_clock::now();
  c.reference = renderReference(field,
                                referenceSettingsFor(settings, outputWidth(renderer, options),
                                                     outputHeight(renderer, options), options),
                                progress);
  c.referenceSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  c.mask = interiorMask(c.reference.terrain, c.reference.width, c.reference.height);

  for (const ComparedMode& m : modes) {
    if (m.prepare) m.prepare();
    ModeError e;
    e.mode = m.name;
    e.frame = modeFrame(renderer, scene, modeSettings(settings, m, options), options);
    const std::vector<glm::vec3> gpu = linearRgb(e.frame);
    e.relativeRmse = relativeRmse(gpu, c.reference.radiance, c.mask);
    double sum = 0;
    size_t count = 0;
    for (size_t i = 0; i < gpu.size(); ++i) {
      const float y = luminance(c.reference.radiance[i]);
      if (!c.mask[i] || y <= 0.0f) continue;
      sum += std::abs(luminance(gpu[i]) - y) / y;
      ++count;
    }
    e.meanRelativeError = count > 0 ? sum / count : 0.0;
    c.modes.push_back(std::move(e));
  }
  return c;
}

void measureShimmer(Comparison& c, TerrainRenderer& renderer, const TerrainScene& scene,
                    const Heightfield& field, const FrameSettings& settings,
                    const std::vector<ComparedMode>& modes, const ComparisonOptions& options,
                    const std::vector<Camera>& cameras,
                    const std::function<void(double)>& progress) {
  if (cameras.size() < 3) {
    throw std::invalid_argument("measureShimmer: a second difference needs three frames");
  }
  if (modes.size() != c.modes.size()) {
    throw std::invalid_argument("measureShimmer: the modes are not the comparison's");
  }
  ShimmerMeter reference;
  ReferenceSettings r = referenceSettingsFor(settings, outputWidth(renderer, options),
                                             outputHeight(renderer, options), options);
  // The reference first, each frame's radiance and mask kept; then each
  // mode along the whole pan, so that an accumulated sequence is one mode's.
  const size_t frames = cameras.size();
  std::vector<std::vector<glm::vec3>> radiance(frames);
  std::vector<std::vector<uint8_t>> masks(frames);
  const double steps = double(frames * (modes.size() + 1));
  for (size_t f = 0; f < frames; ++f) {
    r.camera = cameras[f];
    ReferenceImage image = renderReference(field, r);
    masks[f] = interiorMask(image.terrain, image.width, image.height);
    reference.addFrame(image.radiance, masks[f]);
    radiance[f] = std::move(image.radiance);
    if (progress) progress(double(f + 1) / steps);
  }
  c.referenceShimmer = reference.meanSecondDifference();
  c.panFrames = static_cast<int>(frames);
  for (size_t i = 0; i < modes.size(); ++i) {
    if (modes[i].prepare) modes[i].prepare();
    FrameSettings s = modeSettings(settings, modes[i], options);
    s.camera = cameras.front();
    if (options.temporal) startAccumulation(renderer, scene, s, options.supersample);
    ShimmerMeter meter;
    double error = 0;
    for (size_t f = 0; f < frames; ++f) {
      s.camera = cameras[f];
      const std::vector<glm::vec3> gpu =
          linearRgb(modeFrame(renderer, scene, s, options, options.temporal));
      meter.addFrame(gpu, masks[f]);
      error += relativeRmse(gpu, radiance[f], masks[f]) / double(frames);
      if (progress) progress(double((i + 1) * frames + f + 1) / steps);
    }
    c.modes[i].shimmer = meter.meanSecondDifference();
    c.modes[i].panRelativeRmse = error;
  }
}

std::string comparisonImageName(const std::string& mode) {
  return mode + ".png";
}

std::string comparisonErrorImageName(const std::string& mode) {
  return mode + "-error.png";
}

std::vector<std::string> comparisonFileNames(const std::vector<std::string>& modeNames) {
  std::vector<std::string> names = {kComparisonReferenceLinearName, kComparisonReferenceImageName};
  for (const std::string& mode : modeNames) {
    names.push_back(comparisonImageName(mode));
    names.push_back(comparisonErrorImageName(mode));
  }
  names.push_back(kComparisonTableName);
  return names;
}

void writeComparison(const std::string& folder, const Comparison& c, float exposure) {
  std::filesystem::create_directories(folder);
  const auto path = [&](const std::string& name) {
    return (std::filesystem::path(folder) / name).string();
  };
  const uint32_t w = c.reference.width, h = c.reference.height;

  const FrameResult reference = referenceFrame(c.reference, exposure);
  writeFrame(path(kComparisonReferenceLinearName), reference);
  writeFrame(path(kComparisonReferenceImageName), reference);

  // With a pan: each row's shimmer and its ratio to the reference's, whose
  // own row comes last (its errors against itself are 0).
  const bool pan = c.referenceShimmer.has_value();
  const auto shimmerColumns = [&](double shimmer) {
    const double ratio = *c.referenceShimmer > 0 ? shimmer / *c.referenceShimmer : 0.0;
    std::string columns = ",";  // (appended: GCC 12 misreads "," + std::string as overlapping)
    columns += std::to_string(shimmer);
    columns += ",";
    columns += std::to_string(ratio);
    return columns;
  };
  std::string csv = std::string("mode,relative_rmse,mean_relative_error") +
                    (pan ? ",shimmer,shimmer_vs_reference,pan_relative_rmse" : "") + "\n";
  for (const ModeError& e : c.modes) {
    writeFrame(path(comparisonImageName(e.mode)), e.frame);
    FrameResult error = imageFrame(w, h);
    for (size_t i = 0; i < c.reference.radiance.size(); ++i) {
      uint8_t* px = &error.display[4 * i];
      px[3] = 255;
      if (!c.reference.terrain[i]) {  // sky: blue, so the terrain's outline shows
        px[2] = 96;
        continue;
      }
      const float y = luminance(c.reference.radiance[i]);
      const glm::vec3 g{e.frame.linear[4 * i], e.frame.linear[4 * i + 1],
                        e.frame.linear[4 * i + 2]};
      const float relative = y > 0.0f ? std::abs(luminance(g) - y) / y : 0.0f;
      const auto v = static_cast<uint8_t>(std::lround(255.0f * std::min(1.0f, relative / 0.5f)));
      px[0] = px[1] = px[2] = v;
    }
    writeFrame(path(comparisonErrorImageName(e.mode)), error);
    csv += e.mode + "," + std::to_string(e.relativeRmse) + "," +
           std::to_string(e.meanRelativeError) +
           (pan ? shimmerColumns(e.shimmer.value_or(0)) + "," +
                      std::to_string(e.panRelativeRmse.value_or(0))
                : "") +
           "\n";
  }
  if (pan) csv += "reference,0,0" + shimmerColumns(*c.referenceShimmer) + ",0\n";
  AtomicOutput out(path(kComparisonTableName));
  {
    std::ofstream file(out.temporaryPath());
    file << csv;
    file.flush();
    if (!file) throw out.failure(std::strerror(errno));
  }
  out.commit();
}

}  // namespace aal
