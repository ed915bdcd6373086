// aal-synth: writes a deterministic synthetic DEM (terrain/synthetic.h) as a
// float32 GeoTIFF in a local projected frame (metres, origin at the
// south-west corner), so that large test DEMs are made on demand instead of
// being committed.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <CLI/CLI.hpp>

#include "aperture/terrain/io/atomic_file.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/io/memory_budget.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tools/tool_main.h"
#include "aperture/tools/tool_options.h"

int main(int argc, char** argv) {
  CLI::App app(
      "Writes a synthetic DEM (fBm or ridged value noise, same seed = same heights on\n"
      "every machine) as a float32 GeoTIFF with a local projected georeference.",
      "aal-synth");
  std::string output;
  aal::SyntheticTerrainOptions s;
  int size = 0;
  app.add_option("-o,--output", output, "output GeoTIFF (.tif)")->required();
  app.add_option("--size", size, "side of the square DEM in texels")
      ->required()
      ->check(CLI::Range(1, 32768));
  app.add_option("--seed", s.seed, "noise seed (default 1)");
  app.add_option("--cell-size", s.cellSizeM, "metres between texel centres (default 30)")
      ->check(CLI::Range(1e-3, 1e5));
  app.add_option("--amplitude", s.amplitudeM, "peak-to-peak relief in metres (default 600)")
      ->check(CLI::Range(0.0, 1e5));
  app.add_option("--feature-size", s.featureSizeTexels,
                 "wavelength of the largest features in texels (default 128)")
      ->check(CLI::Range(1.0, 1e6));
  app.add_option("--octaves", s.octaves, "noise octaves (default 7)")->check(CLI::Range(1, 16));
  app.add_flag("--ridged", s.ridged, "sharp ridges instead of rounded hills");

  return aal::runTool(app, argc, argv, [&] {
    s.width = s.height = size;
    // The writer makes a GeoTIFF whatever the name says: a name that says
    // otherwise (x.png) would mislead every program that trusts it.
    std::string extension = std::filesystem::path(output).extension().string();
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (extension != ".tif" && extension != ".tiff") {
      throw aal::InputError("-o " + output +
                            ": aal-synth writes a GeoTIFF; give a name ending in .tif or .tiff");
    }
    aal::requireWritableOutput(output);
    // The heights are held whole (4 bytes per texel) while GDAL writes them:
    // refused with the numbers when they do not fit, as the other tools
    // refuse a DEM (terrain/io/memory_budget.h, AAL_MEMORY_LIMIT).
    aal::requireMemory(output, 4.0 * size * size,
                       "its " + std::to_string(size) + " x " + std::to_string(size) + " heights",
                       std::getenv("AAL_MEMORY_LIMIT")
                           ? "give a smaller --size, or a larger AAL_MEMORY_LIMIT"
                           : "give a smaller --size");
    const aal::Heightfield field = aal::makeSyntheticTerrain(s);
    aal::GeoReference geo;
    geo.crs = aal::CrsKind::Projected;
    geo.stepX = geo.stepY = s.cellSizeM;
    geo.originX = 0.5 * s.cellSizeM;
    geo.originY = (size - 0.5) * s.cellSizeM;
    aal::writeFloatGeoTiff(output, field.width, field.height, field.z.data(), geo);
    const auto [lo, hi] = std::minmax_element(field.z.begin(), field.z.end());
    std::printf("aal-synth: wrote %s (%d x %d, %g m cells, heights %.1f .. %.1f m, %s seed %llu)\n",
                output.c_str(), size, size, s.cellSizeM, *lo, *hi, s.ridged ? "ridged" : "fBm",
                static_cast<unsigned long long>(s.seed));
    return aal::kExitOk;
  });
}
