#include "aperture/tools/options/geotiff_output_options.h"

#include <cctype>

#include "aperture/terrain/errors.h"

namespace aal {

namespace {

std::string upper(std::string text) {
  for (char& c : text) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return text;
}

// -of and --cog.
void addFormatOptions(CLI::App& app, GeoTiffOutputOptions& output, const std::string& outputs) {
  app.add_option("--of", output.format,
                 "-of: the format of " + outputs +
                     ": GTiff (a tiled GeoTIFF, the default) or COG (a cloud-optimized GeoTIFF: "
                     "tiled, with averaged overviews, ordered for HTTP range reads), as "
                     "gdal_translate -of")
      ->check(CLI::IsMember({"GTiff", "COG"}, CLI::ignore_case));
  app.add_flag("--cog", output.cog, "the same as -of COG");
}

}  // namespace

void addGeoTiffOutputOptions(CLI::App& app, GeoTiffOutputOptions& output,
                             const std::string& outputs, bool formats) {
  if (formats) addFormatOptions(app, output, outputs);
  app.add_option("--co", output.creationOptions,
                 "-co: a GDAL creation option KEY=VALUE for " + outputs +
                     ", repeatable, as gdal_translate -co; it overrides ours (COMPRESS=DEFLATE, "
                     "ZLEVEL=1 for floats, PREDICTOR, TILED=YES, BIGTIFF=IF_SAFER; the keys: "
                     "`gdalinfo --format "
                     "GTiff`" +
                     (formats ? std::string(", or COG") : std::string()) +
                     "), e.g. -co COMPRESS=LZW; checked before any work")
      ->allow_extra_args(false);
  app.add_flag("--overviews", output.overviews,
               "add internal overviews to " + outputs +
                   " (averaged halvings down to one 256-pixel tile, as gdaladdo -r average)" +
                   (formats ? "; a COG has its own, down to one 512-pixel tile" : ""));
}

GdalArguments::GdalArguments(int argc, char** argv) : arguments_(argv, argv + argc) {
  for (std::string& argument : arguments_) {
    if (argument == "--") break;
    for (const char* gdal : {"-co", "-of"}) {
      const std::string name = gdal;
      if (argument == name || argument.rfind(name + "=", 0) == 0) argument.insert(0, "-");
    }
  }
  for (std::string& argument : arguments_) pointers_.push_back(argument.data());
}

RasterWriteOptions rasterWriteOptions(const GeoTiffOutputOptions& output) {
  const std::string format = upper(output.format);
  if (output.cog && format == "GTIFF") {
    throw InputError("--cog is -of COG: leave out -of " + output.format);
  }
  RasterWriteOptions options;
  options.cog = output.cog || format == "COG";
  options.creationOptions = output.creationOptions;
  options.overviews = output.overviews;
  checkCreationOptions(options);
  return options;
}

}  // namespace aal
