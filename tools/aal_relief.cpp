// aal-relief: a top-down shaded-relief map of a DEM, lit by ambient aperture
// lighting, as a GeoTIFF placed exactly like the DEM (docs/relief.md).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "aperture/preprocess/aperture_cache.h"
#include "aperture/preprocess/progress_reporter.h"
#include "aperture/terrain/interrupt.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/io/band_labels.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/dem_options.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/io/memory_budget.h"
#include "aperture/terrain/light/lighting_defaults.h"
#include "aperture/terrain/light/solar_position.h"
#include "aperture/terrain/reference/color_ramp.h"
#include "aperture/terrain/reference/relief.h"
#include "aperture/terrain/view/camera.h"
#include "aperture/tools/options/dem_units_options.h"
#include "aperture/tools/options/geotiff_output_options.h"
#include "aperture/tools/options/output_options.h"
#include "aperture/tools/options/sun_options.h"
#include "aperture/tools/tool_main.h"
#include "aperture/tools/tool_options.h"
#include "aperture/tools/tool_paths.h"

namespace {

struct Options {
  std::string dem, output, aperture;
  std::string resolution;
  aal::SunOptions sun;
  std::optional<double> skyWeight;  // default kDefaultSkyWeight
  bool skyOnly = false, multidirectional = false;
  std::string mode = "approx";
  bool noObscurance = false;
  std::optional<double> obscuranceRadiusM;
  int obscuranceSamples = 16, obscuranceSteps = 1;
  std::string colorRelief, palette;
  std::string format = "byte";
  std::string stretch;
  std::optional<double> waterLevel;
  std::string waterMask;
  aal::GeoTiffOutputOptions geotiff;  // -of, -co, --overviews
  aal::DemUnitsOptions units;
  aal::ProgressOptions report;
};

// The sky's share of the light by default: enough fill that slopes facing
// away from the sun keep their form, the sun still dominant.
constexpr double kDefaultSkyWeight = 0.2;

// Water in colour maps: a muted blue (sRGB 0..255), shaded like the land.
constexpr float kWaterRgb[3] = {90, 140, 190};

bool endsWith(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  return std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                    [](char a, char b) { return std::tolower(a) == std::tolower(b); });
}

// --resolution: "Nm" (or a plain number) is the pixel size in metres along
// the DEM's rows' spacing (north-south; x keeps the DEM's aspect), "Nx" a
// scale factor on the pixels per side (2x: twice as many, 0.5x: half).
// Returns the output size; the DEM's extent is kept.
std::pair<int, int> outputSize(const std::string& text, const aal::Heightfield& field) {
  if (text.empty()) return {field.width, field.height};
  std::string number = text;
  bool factor = false;
  if (endsWith(number, "x")) {
    factor = true;
    number.pop_back();
  } else if (endsWith(number, "m")) {
    number.pop_back();
  }
  const char* begin = number.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  if (end == begin || *end != '\0' || !std::isfinite(v) || v <= 0) {
    throw aal::InputError(
        "--resolution must be a pixel size in metres (30 or 30m) or a scale "
        "factor (2x, 0.5x), positive, got '" +
        text + "'");
  }
  const double scale = factor ? v : field.cellSizeYM / v;
  const double w = std::round(field.width * scale), h = std::round(field.height * scale);
  if (w < 1 || h < 1 || w > aal::kMaxDemSide || h > aal::kMaxDemSide) {
    throw aal::InputError("--resolution " + text + " gives " + std::to_string(int64_t(w)) + " x " +
                          std::to_string(int64_t(h)) + " pixels; the output must be 1 to " +
                          std::to_string(aal::kMaxDemSide) + " pixels per side");
  }
  return {static_cast<int>(w), static_cast<int>(h)};
}

// --stretch LOW,HIGH: the relief values mapped to the full 8-bit range.
std::pair<double, double> parseStretch(const std::string& text) {
  if (text.empty()) return {0.0, 1.0};
  std::istringstream in(text);
  double low = 0, high = 0;
  char comma = 0;
  if (!(in >> low >> comma >> high) || comma != ',' || !in.eof() || !(low >= 0) || !(high <= 1) ||
      !(low < high)) {
    throw aal::InputError("--stretch must be LOW,HIGH with 0 <= LOW < HIGH <= 1, got '" + text +
                          "'");
  }
  return {low, high};
}

// The GeoTIFF's write options: -of, -co, --overviews, checked.
aal::RasterWriteOptions checkOptions(const Options& o) {
  // Against every file read: the rasters' (a VRT's sources too), a tiled
  // aperture map's.
  aal::NamedPaths inputs = aal::inputFiles("DEM", o.dem, /*raster=*/true);
  aal::append(inputs, aal::inputFiles("--aperture", o.aperture));
  aal::append(inputs, aal::inputFiles("--water-mask", o.waterMask, /*raster=*/true));
  inputs.push_back({"--color-relief", o.colorRelief});
  aal::checkDistinctFiles(inputs, {{"-o", o.output}});
  if (!endsWith(o.output, ".tif") && !endsWith(o.output, ".tiff")) {
    throw aal::InputError("output " + o.output + " must end in .tif or .tiff (a GeoTIFF)");
  }
  aal::requireWritableOutput(o.output);
  const bool sunGiven = o.sun.azimuthDeg || o.sun.elevationDeg || !o.sun.time.empty();
  if (o.skyOnly && (sunGiven || o.multidirectional || o.skyWeight)) {
    throw aal::InputError(
        "--sky-only has no sun: leave out --sun-azimuth, --sun-elevation, --time, "
        "--multidirectional and --sky");
  }
  if (!o.sun.time.empty() && (o.sun.azimuthDeg || o.sun.elevationDeg)) {
    throw aal::InputError("give --time or --sun-azimuth/--sun-elevation, not both");
  }
  if (o.sun.time.empty() && (o.sun.latitudeDeg || o.sun.longitudeDeg)) {
    throw aal::InputError("--lat and --lon place the sun for --time; give --time too");
  }
  if (o.multidirectional && (o.sun.azimuthDeg || !o.sun.time.empty())) {
    throw aal::InputError(
        "--multidirectional lights from 225, 270, 315 and 360 degrees: leave "
        "out --sun-azimuth and --time (--sun-elevation sets their elevation)");
  }
  if (!o.colorRelief.empty() && !o.palette.empty()) {
    throw aal::InputError("give --color-relief or --palette, not both");
  }
  const bool colour = !o.colorRelief.empty() || !o.palette.empty();
  if (colour && o.format == "float") {
    throw aal::InputError("colour relief is 8-bit RGB: leave out --format float");
  }
  if (!o.stretch.empty() && o.format == "float") {
    throw aal::InputError("--stretch is for 8-bit output: --format float keeps the values");
  }
  parseStretch(o.stretch);
  if (o.waterLevel && !o.waterMask.empty()) {
    throw aal::InputError("give --water-level or --water-mask, not both");
  }
  return aal::rasterWriteOptions(o.geotiff);
}

// Non-zero, non-void texels of a raster the DEM's size are water.
std::vector<uint8_t> readWaterMask(const std::string& path, const aal::Heightfield& field) {
  const aal::Heightfield mask = aal::loadDem(path);
  if (mask.width != field.width || mask.height != field.height) {
    throw aal::InputError("--water-mask " + path + " is " + std::to_string(mask.width) + " x " +
                          std::to_string(mask.height) + " texels; it must have the DEM's size (" +
                          std::to_string(field.width) + " x " + std::to_string(field.height) + ")");
  }
  std::vector<uint8_t> water(mask.texelCount());
  for (int y = 0; y < mask.height; ++y) {
    for (int x = 0; x < mask.width; ++x) {
      water[mask.index(x, y)] = !mask.isVoid(x, y) && mask.at(x, y) != 0.0f ? 1 : 0;
    }
  }
  return water;
}

aal::Heightfield loadReliefDem(const Options& o) {
  aal::DemLoadOptions load;
  aal::applyDemUnits(o.units, load);
  load.peakBytesPerTexel = aal::kReliefBytesPerTexel;
  load.workName = "a relief";
  load.memoryHint =
      "cut the DEM (`gdal_translate -srcwin`) or coarsen it (`gdal_translate -outsize 50% 50%`)";
  aal::Heightfield field = aal::loadDem(o.dem, load);
  aal::requireRenderableDem(field);
  return field;
}

// The shading the options ask for, at outWidth x outHeight; a note when
// --time puts the sun below the horizon.
aal::ReliefSettings reliefSettings(const Options& o, const aal::Heightfield& field, int outWidth,
                                   int outHeight, bool keepHeights) {
  aal::ReliefSettings s;
  s.outWidth = outWidth;
  s.outHeight = outHeight;
  s.mode = o.mode == "exact" ? aal::ShadingMode::Exact : aal::ShadingMode::Approx;
  s.sunRadiusDeg = o.sun.radiusDeg;
  s.skyWeight = static_cast<float>(o.skyWeight.value_or(kDefaultSkyWeight));
  s.lighting = o.skyOnly            ? aal::ReliefLighting::SkyOnly
               : o.multidirectional ? aal::ReliefLighting::Multidirectional
                                    : aal::ReliefLighting::Sun;
  const aal::SolarPosition sun = aal::sunOf(o.sun, field);
  s.sunAzimuthDeg = sun.azimuthDeg;
  s.sunElevationDeg = sun.elevationDeg;
  if (!o.sun.time.empty() && sun.elevationDeg < -o.sun.radiusDeg && !o.report.quiet) {
    std::fprintf(stderr, "note: the sun is %.1f deg below the horizon then: sky light only\n",
                 -sun.elevationDeg);
  }
  s.obscurance = aal::obscuranceFromOptions(!o.noObscurance, o.obscuranceSamples, o.obscuranceSteps,
                                            o.obscuranceRadiusM, field);
  s.keepHeights = keepHeights;
  s.waterLevelM = o.waterLevel;
  if (!o.waterMask.empty()) s.waterMask = readWaterMask(o.waterMask, field);
  return s;
}

// The aperture map as halves (8 bytes a texel), as the renderer holds it:
// --aperture checked against the DEM, else the cached or baked map.
aal::HalfApertureMap halfApertureMap(const Options& o, const aal::Heightfield& field) {
  if (!o.aperture.empty()) {
    aal::ApertureMapReader reader(o.aperture);
    aal::checkApertureMatchesDem(reader.header(), o.aperture, field, o.dem);
    return aal::readHalfApertureMap(reader);
  }
  aal::CachedAperture cached =
      aal::cachedOrBakedAperture(field, o.dem, aal::BakeOptions{}, o.report.style(), o.report.quiet,
                                 {o.waterMask, o.colorRelief});
  if (cached.path.empty()) return aal::toHalfApertureMap(cached.map);
  aal::ApertureMapReader reader(cached.path.string());
  return aal::readHalfApertureMap(reader);
}

// A relief value through --stretch LOW,HIGH, clamped to [0, 1].
float stretched(float v, const std::pair<double, double>& stretch) {
  const auto [low, high] = stretch;
  return static_cast<float>(std::clamp((v - low) / (high - low), 0.0, 1.0));
}

// The lowest and highest heights of the DEM's texels that are not void.
std::pair<double, double> heightRange(const aal::Heightfield& field) {
  double zMin = std::numeric_limits<double>::infinity(), zMax = -zMin;
  for (int y = 0; y < field.height; ++y) {
    for (int x = 0; x < field.width; ++x) {
      if (field.isVoid(x, y)) continue;
      zMin = std::min(zMin, double(field.at(x, y)));
      zMax = std::max(zMax, double(field.at(x, y)));
    }
  }
  return {zMin, zMax};
}

// The colour bands' descriptions (their colour interpretation is set too).
aal::RasterWriteOptions colourLabels(int bands, aal::RasterWriteOptions write) {
  static const char* const kNames[] = {"shaded colour relief (red)", "shaded colour relief (green)",
                                       "shaded colour relief (blue)", "alpha (0: nodata)"};
  write.bandLabels.clear();
  for (int b = 0; b < bands; ++b) write.bandLabels.push_back({kNames[b], ""});
  return write;
}

// Colour from the ramp at the pixel's height, times the shading; voids
// take the ramp's nv colour, else transparent black (an alpha band).
void writeColourRelief(const Options& o, const aal::Heightfield& field,
                       const aal::ReliefImage& relief, const aal::ColorRamp& ramp,
                       const aal::GeoReference& geo, const aal::RasterWriteOptions& write) {
  const auto [zMin, zMax] = heightRange(field);
  const aal::ResolvedColorRamp resolved = aal::resolveColorRamp(ramp, zMin, zMax);
  bool alpha = field.voidCount > 0;
  for (const glm::vec4& c : resolved.rgba) alpha = alpha || c.a < 255;
  const int bands = alpha ? 4 : 3;
  const size_t pixels = relief.value.size();
  const std::pair<double, double> stretch = parseStretch(o.stretch);
  std::vector<uint8_t> rgb(pixels * bands);
  const glm::vec4 nodataColour = resolved.nodata.value_or(glm::vec4(0));
  for (size_t i = 0; i < pixels; ++i) {
    glm::vec4 c;
    if (relief.isVoid(i)) {
      c = nodataColour;
    } else {
      c = !relief.water.empty() && relief.water[i]
              ? glm::vec4(kWaterRgb[0], kWaterRgb[1], kWaterRgb[2], 255)
              : aal::rampColor(resolved, relief.heightM[i]);
      c = glm::vec4(glm::vec3(c) * stretched(relief.value[i], stretch), c.a);
    }
    for (int b = 0; b < bands; ++b) {
      rgb[i * bands + b] = static_cast<uint8_t>(std::clamp(std::lround(c[b]), 0L, 255L));
    }
  }
  aal::writeGeoTiff(
      o.output,
      aal::RasterImage{relief.width, relief.height, bands, aal::RasterSampleType::Byte, rgb.data()},
      geo, colourLabels(bands, write));
}

// gdaldem's scale: 1 + 254 v, 0 reserved for nodata.
void writeGreyRelief(const Options& o, const aal::Heightfield& field,
                     const aal::ReliefImage& relief, const aal::GeoReference& geo,
                     aal::RasterWriteOptions write) {
  const std::pair<double, double> stretch = parseStretch(o.stretch);
  std::vector<uint8_t> grey(relief.value.size());
  for (size_t i = 0; i < grey.size(); ++i) {
    grey[i] =
        relief.isVoid(i)
            ? 0
            : static_cast<uint8_t>(1 + std::lround(254.0 * stretched(relief.value[i], stretch)));
  }
  if (field.voidCount > 0 || field.nodata) write.nodata = 0;
  write.bandLabels = {aal::reliefBandLabel(/*bytes=*/true)};
  aal::writeGeoTiff(
      o.output,
      aal::RasterImage{relief.width, relief.height, 1, aal::RasterSampleType::Byte, grey.data()},
      geo, write);
}

// -o as colour, float or grey, placed like the DEM.
// Float: NaN is the nodata value, declared whether or not there are voids.
void writeRelief(const Options& o, const aal::Heightfield& field, const aal::ReliefImage& relief,
                 const std::optional<aal::ColorRamp>& ramp, aal::RasterWriteOptions write) {
  const aal::GeoReference geo =
      aal::resampledGeoReference(field.geo, field.width, field.height, relief.width, relief.height);
  if (ramp) {
    writeColourRelief(o, field, relief, *ramp, geo, write);
  } else if (o.format == "float") {
    write.nodata = std::numeric_limits<double>::quiet_NaN();
    write.bandLabels = {aal::reliefBandLabel(/*bytes=*/false)};
    aal::writeFloatGeoTiff(o.output, relief.width, relief.height, relief.value.data(), geo, write);
  } else {
    writeGreyRelief(o, field, relief, geo, write);
  }
}

// The one line on stderr: the size, the light and the time.
void printSummary(const Options& o, const aal::ReliefSettings& s, double seconds) {
  char light[96];
  if (o.skyOnly) {
    std::snprintf(light, sizeof light, "sky only");
  } else if (o.multidirectional) {
    std::snprintf(light, sizeof light, "multidirectional, elevation %.1f deg, sky %.2f",
                  s.sunElevationDeg, double(s.skyWeight));
  } else {
    std::snprintf(light, sizeof light, "sun azimuth %.1f deg, elevation %.1f deg, sky %.2f",
                  s.sunAzimuthDeg, s.sunElevationDeg, double(s.skyWeight));
  }
  std::fprintf(stderr, "aal-relief: %dx%d pixels (%s) in %.2f s, wrote %s\n", s.outWidth,
               s.outHeight, light, seconds, o.output.c_str());
}

int run(const Options& o) {
  const aal::RasterWriteOptions write = checkOptions(o);
  std::optional<aal::ColorRamp> ramp;
  if (!o.colorRelief.empty()) ramp = aal::readColorRamp(o.colorRelief);
  if (!o.palette.empty()) ramp = aal::builtinPalette(o.palette);
  const aal::Heightfield field = loadReliefDem(o);
  const auto [outWidth, outHeight] = outputSize(o.resolution, field);
  const aal::ReliefSettings s = reliefSettings(o, field, outWidth, outHeight, ramp.has_value());
  aal::HalfApertureMap map = halfApertureMap(o, field);

  const auto start = std::chrono::steady_clock::now();
  aal::ProgressReporter bar(o.report.style(), "shading", "shading");
  const aal::ReliefImage relief = aal::shadeRelief(field, map, s, [&](double f) { bar.update(f); });
  bar.finish();
  map = {};
  writeRelief(o, field, relief, ramp, write);
  if (!o.report.quiet) {
    printSummary(o, s,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return aal::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app(
      "Writes a top-down shaded relief of a DEM as a GeoTIFF placed exactly like the DEM (one "
      "pixel per DEM texel by default): the sun through the aperture map's visible sky (soft "
      "cast shadows), sky fill and near-field obscurances (docs/relief.md).\n"
      "The value is (1-k) f cos + k sky, in [0, 1]: 8-bit 1 + 254 v like gdaldem hillshade "
      "(0 = nodata), or float32. Without --aperture the aperture map is baked once and cached "
      "(see aal-bake).",
      "aal-relief");
  Options o;
  app.add_option("dem", o.dem, "input DEM (any raster GDAL reads)")->required();
  app.add_option("-o,--output", o.output, "output GeoTIFF (.tif)")->required();
  app.add_option("--aperture", o.aperture, "aperture map baked from this DEM by aal-bake");
  app.add_option("--resolution", o.resolution,
                 "output pixel size: metres (30 or 30m, along the DEM's north-south spacing) or "
                 "a scale factor on the pixels per side (2x, 0.5x); the DEM's extent is kept "
                 "(default: one pixel per DEM texel)");
  aal::addSunOptions(app, o.sun);
  app.add_option("--sky", o.skyWeight,
                 "sky weight k: the sky's share of the light (default 0.2; 0: the sun alone, "
                 "like gdaldem)")
      ->check(CLI::Range(0.0, 1.0));
  app.add_flag("--sky-only", o.skyOnly,
               "diffuse sky-view relief: the sky term alone (1 on open flat ground, darker in "
               "valleys and on steep slopes)");
  app.add_flag("--multidirectional", o.multidirectional,
               "suns at 225, 270, 315 and 360 deg weighted by the slope's aspect "
               "(gdaldem -multidirectional's weights, Mark 1992)");
  app.add_option("--mode", o.mode, "sun-aperture cap intersection: approx (Oat's) or exact")
      ->check(CLI::IsMember({"approx", "exact"}))
      ->capture_default_str();
  app.add_flag("--no-obscurance", o.noObscurance, "no near-field obscurances on the sky term");
  app.add_option("--obscurance-radius", o.obscuranceRadiusM,
                 "near-field radius of the obscurances in metres (default: 10 DEM cells)");
  app.add_option("--obscurance-samples", o.obscuranceSamples,
                 "obscurance sample count: 8, 16 or 32")
      ->capture_default_str();
  app.add_option("--obscurance-steps", o.obscuranceSteps, "obscurance test points per ray: 1 or 2")
      ->capture_default_str();
  app.add_option("--color-relief", o.colorRelief,
                 "colour ramp file in gdaldem color-relief's format (elevation R G B [A]; "
                 "percentages like 50%; nv for nodata): RGB output, ramp colour times shading");
  std::string palettes;
  for (const std::string& n : aal::builtinPaletteNames())
    palettes += (palettes.empty() ? "" : ", ") + n;
  app.add_option("--palette", o.palette,
                 "built-in colour ramp over the DEM's height range: " + palettes);
  app.add_option(
         "--format", o.format,
         "grey output: byte (1 + 254 v: 1..255, 0 = nodata) or float (v in 0..1, NaN = nodata)")
      ->check(CLI::IsMember({"byte", "float"}))
      ->capture_default_str();
  app.add_option("--stretch", o.stretch,
                 "LOW,HIGH: relief values from LOW to HIGH fill the 8-bit range (default 0,1); "
                 "e.g. 0.65,1 for --sky-only, whose values on gentle terrain stay near 1");
  app.add_option("--water-level", o.waterLevel,
                 "heights at or below this many metres are water: lit flat (blue in colour "
                 "maps); no water by default");
  app.add_option("--water-mask", o.waterMask,
                 "raster of the DEM's size, non-zero where there is water (instead of "
                 "--water-level)");
  aal::addGeoTiffOutputOptions(app, o.geotiff, "the output");
  aal::addDemUnitsOptions(app, o.units);
  aal::addProgressOptions(app, o.report);

  aal::GdalArguments arguments(argc, argv);
  return aal::runTool(app, arguments.argc(), arguments.argv(), [&] { return run(o); });
}
