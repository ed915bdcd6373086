// aal-caps: exact vs approximate (Oat) spherical-cap intersection, for one
// configuration or as an error table and plot over a grid.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "aperture/terrain/io/atomic_file.h"
#include "aperture/terrain/light/cap_error.h"
#include "aperture/terrain/units.h"
#include "aperture/tools/cap_error_plot.h"
#include "aperture/tools/tool_main.h"
#include "aperture/tools/tool_options.h"
#include "aperture/tools/tool_paths.h"

namespace {

struct Options {
  std::vector<std::string> values;  // R0 R1 D
  bool degrees = false;
  bool json = false;
  std::string tablePath;
  std::string plotPath;
  std::optional<double> maxRadius;
  int steps = 48;
};

// Parses an angle given on the command line into radians in [0, pi].
double parseAngle(const std::string& name, const std::string& text, bool degrees) {
  double value = 0.0;
  size_t used = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || text.empty()) {
    throw aal::InputError(name + " must be a number, got '" + text + "'");
  }
  const double limit = degrees ? 180.0 : aal::kPi;
  if (!std::isfinite(value) || value < 0.0 || value > limit) {
    throw aal::InputError(name + " must be in [0, " + (degrees ? "180] degrees" : "pi] radians") +
                          ", got " + text);
  }
  return degrees ? value / aal::kDegreesPerRadian : value;
}

int printOne(const Options& o) {
  if (o.values.size() != 3) {
    throw aal::InputError("expected R0 R1 D (three angles), or --table/--plot; see --help");
  }
  const double r0 = parseAngle("R0", o.values[0], o.degrees);
  const double r1 = parseAngle("R1", o.values[1], o.degrees);
  const double d = parseAngle("D", o.values[2], o.degrees);
  const aal::CapErrorSample s = aal::evaluateCapError(r0, r1, d);
  if (o.json) {
    std::printf("{\"exact\": %.9g, \"approx\": %.9g, \"abs_error\": %.9g, \"rel_error\": %.9g}\n",
                s.exact, s.approx, s.absError, s.relError);
  } else {
    std::printf("exact      %.6f sr\n", s.exact);
    std::printf("approx     %.6f sr\n", s.approx);
    std::printf("abs_error  %.6f sr\n", s.absError);
    std::printf("rel_error  %.4f %s\n", s.relError,
                "(of the smaller cap's area, the largest the intersection can be)");
  }
  return aal::kExitOk;
}

void writeTable(const std::string& path, const std::vector<aal::CapErrorSample>& samples) {
  aal::AtomicOutput output(path);
  {
    std::ofstream out(output.temporaryPath());
    out << "r0_rad,r1_rad,d_rad,exact_sr,approx_sr,abs_error_sr,rel_error,partial\n";
    char line[256];
    for (const aal::CapErrorSample& s : samples) {
      std::snprintf(line, sizeof line, "%.6f,%.6f,%.6f,%.8g,%.8g,%.8g,%.8g,%d\n", s.r0Rad, s.r1Rad,
                    s.dRad, s.exact, s.approx, s.absError, s.relError, s.partial ? 1 : 0);
      out << line;
    }
    if (!out.flush()) throw output.failure(std::strerror(errno), "table");
  }
  output.commit();
}

void printSummary(const std::vector<aal::CapErrorSample>& samples, double maxRadius) {
  std::printf(
      "Oat's approximation vs exact, partially overlapping caps, error relative to the "
      "smaller cap's area:\n");
  const double limits[] = {aal::kPi / 2, maxRadius};
  for (double limit : limits) {
    if (limit > maxRadius + 1e-12) continue;
    const aal::CapErrorSummary s = aal::summarizeCapError(samples, limit);
    std::printf("  radii <= %5.1f deg: mean %5.2f%%  max %6.2f%%  (%zu configurations)\n",
                aal::degrees(limit), 100 * s.meanRelError, 100 * s.maxRelError, s.count);
    if (limit >= maxRadius) break;
  }
}

int sweep(const Options& o) {
  if (!o.values.empty()) throw aal::InputError("give either R0 R1 D or --table/--plot, not both");
  double maxRadius = aal::kPi;
  if (o.maxRadius) {
    const double limit = o.degrees ? 180.0 : aal::kPi;
    if (!std::isfinite(*o.maxRadius) || *o.maxRadius <= 0.0 || *o.maxRadius > limit) {
      throw aal::InputError("--max-radius must be in (0, " +
                            std::string(o.degrees ? "180] degrees" : "pi] radians"));
    }
    maxRadius = o.degrees ? *o.maxRadius / aal::kDegreesPerRadian : *o.maxRadius;
  }
  aal::checkDistinctFiles({}, {{"--table", o.tablePath}, {"--plot", o.plotPath}});
  if (!o.tablePath.empty()) aal::requireWritableOutput(o.tablePath);
  if (!o.plotPath.empty()) {
    // Found before the sweep, not by the image writer after it.
    const std::filesystem::path extension = std::filesystem::path(o.plotPath).extension();
    if (extension != ".png" && extension != ".PNG") {
      throw aal::InputError("--plot " + o.plotPath + " must end in .png (the plot is a PNG)");
    }
    aal::requireWritableOutput(o.plotPath);
  }

  const std::vector<aal::CapErrorSample> samples =
      aal::sweepCapError(o.steps, 2 * o.steps, maxRadius);
  if (!o.tablePath.empty()) {
    writeTable(o.tablePath, samples);
    std::printf("table: %s (%zu rows)\n", o.tablePath.c_str(), samples.size());
  }
  if (!o.plotPath.empty()) {
    aal::CapErrorPlotOptions plot;
    plot.maxRadiusRad = maxRadius;
    for (double fraction : {1.0 / 12, 1.0 / 4, 1.0 / 2, 3.0 / 4}) {
      plot.r0ValuesRad.push_back(fraction * maxRadius);
    }
    aal::writeCapErrorPlot(o.plotPath, plot);
    std::printf("plot:  %s\n", o.plotPath.c_str());
  }
  printSummary(samples, maxRadius);
  return aal::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app(
      "Compares the exact intersection area of two spherical caps with Oat's smoothstep\n"
      "approximation (Ambient Aperture Lighting, SIGGRAPH 2006).\n\n"
      "  aal-caps R0 R1 D              one configuration: cap radii R0, R1 and the angle D\n"
      "                                between their centres (radians, or --degrees)\n"
      "  aal-caps --table T.csv --plot P.png   sweep a grid, write the error table and plot\n\n"
      "Relative errors are given as a fraction of the smaller cap's area.",
      "aal-caps");
  Options o;
  app.add_option("angles", o.values,
                 "R0 R1 D: two cap radii and the distance between centres, "
                 "each in [0, pi] radians ([0, 180] with --degrees)");
  app.add_flag("--degrees", o.degrees, "angles are in degrees instead of radians");
  app.add_flag("--json", o.json, "print one JSON object {exact, approx, abs_error, rel_error}");
  app.add_option("--table", o.tablePath, "write the error table over the grid as CSV");
  app.add_option("--plot", o.plotPath, "write a PNG picture of the error over (d, r1) for four r0");
  app.add_option("--max-radius", o.maxRadius,
                 "largest cap radius of the sweep (default pi, i.e. 180 degrees)");
  app.add_option("--steps", o.steps, "radius steps of the sweep grid (distance: twice as many)")
      ->check(CLI::Range(4, 512));

  return aal::runTool(app, argc, argv, [&] {
    return (o.tablePath.empty() && o.plotPath.empty()) ? printOne(o) : sweep(o);
  });
}
