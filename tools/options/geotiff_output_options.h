// How a tool writes its GeoTIFFs, on its command line (aal-bake,
// aal-relief): -of GTiff|COG (--cog for -of COG), -co KEY=VALUE as
// gdal_translate's, --overviews. docs/baking.md and docs/relief.md.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "aperture/terrain/io/geotiff_writer.h"

namespace aal {

struct GeoTiffOutputOptions {
  std::string format;                        // -of: GTiff or COG; "": GTiff unless --cog
  bool cog = false;                          // --cog: -of COG
  std::vector<std::string> creationOptions;  // -co KEY=VALUE, repeatable
  bool overviews = false;                    // --overviews
};

// -of, --cog (unless `formats` is false: a tool that writes only plain
// GeoTIFF tiles), -co and --overviews. `outputs` names what they apply to
// ("--svf and --visible"), in their help. CLI11 takes short options of one
// letter only: GDAL's -co and -of are --co and --of to it (GdalArguments).
void addGeoTiffOutputOptions(CLI::App& app, GeoTiffOutputOptions& output,
                             const std::string& outputs, bool formats = true);

// The command line with GDAL's -co and -of (also -co=X) spelled --co and
// --of, up to a "--", for CLI11; the rest as given.
class GdalArguments {
 public:
  GdalArguments(int argc, char** argv);
  int argc() const { return static_cast<int>(pointers_.size()); }
  char** argv() { return pointers_.data(); }

 private:
  std::vector<std::string> arguments_;
  std::vector<char*> pointers_;
};

// The options as RasterWriteOptions (format, creation options, overviews;
// the rest default). Throws InputError for --cog with -of GTiff, and as
// checkCreationOptions (a -co that is not KEY=VALUE, or one GDAL's driver
// refuses), so that a tool refuses them before its work.
RasterWriteOptions rasterWriteOptions(const GeoTiffOutputOptions& output);

}  // namespace aal
