// aal-info: what aperture reads from a DEM file, like gdalinfo: format, size,
// CRS, metric cell size, geographic centre, height range and voids.
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/dem_source.h"
#include "aperture/terrain/io/dem_summary.h"
#include "aperture/tools/options/dem_units_options.h"
#include "aperture/tools/tool_main.h"

namespace {

struct Options {
  std::string dem;
  bool json = false;
  aal::DemUnitsOptions units;
};

const char* crsName(aal::CrsKind crs) {
  switch (crs) {
    case aal::CrsKind::Geographic: return "geographic";
    case aal::CrsKind::Projected: return "projected";
    case aal::CrsKind::None: break;
  }
  return "none";
}

std::string jsonString(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
      out += escaped;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

// A JSON number, or a string for NaN and infinities (JSON has no such numbers).
std::string jsonNumber(double value) {
  char text[64];
  if (std::isnan(value)) return "\"nan\"";
  if (std::isinf(value)) return value > 0 ? "\"inf\"" : "\"-inf\"";
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

std::string jsonStringOrNull(const std::string& text) {
  return text.empty() ? "null" : jsonString(text);
}

std::string horizontalUnit(const aal::GeoReference& geo) {
  switch (geo.crs) {
    case aal::CrsKind::Geographic: return geo.angularUnitDeg == 1.0 ? "degree" : "angular unit";
    case aal::CrsKind::Projected: {
      if (geo.linearUnitM == 1.0) return "metre";
      if (geo.linearUnitM == 0.3048) return "foot";
      if (std::abs(geo.linearUnitM - 1200.0 / 3937.0) < 1e-12) return "US survey foot";
      char text[64];
      std::snprintf(text, sizeof text, "%.10g m", geo.linearUnitM);
      return text;
    }
    case aal::CrsKind::None: break;
  }
  return {};
}

void printJson(const aal::Heightfield& f, const aal::DemSummary& s) {
  std::printf("{\"format\": %s, \"driver\": %s, \"width\": %d, \"height\": %d, \"crs\": \"%s\", ",
              jsonString(f.format).c_str(), jsonStringOrNull(f.driver).c_str(), f.width, f.height,
              crsName(f.geo.crs));
  std::printf("\"crs_name\": %s, ", jsonStringOrNull(f.geo.crsName).c_str());
  if (f.geo.epsg > 0) {
    std::printf("\"epsg\": %d, ", f.geo.epsg);
  } else {
    std::printf("\"epsg\": null, ");
  }
  std::printf("\"cell_size_m\": [%.9g, %.9g], ", f.cellSizeXM, f.cellSizeYM);
  if (f.geo.hasCenter) {
    std::printf("\"center_lat\": %.9f, \"center_lon\": %.9f, ", f.geo.centerLatDeg,
                f.geo.centerLonDeg);
  } else {
    std::printf("\"center_lat\": null, \"center_lon\": null, ");
  }
  std::printf("\"nodata\": %s, ", f.nodata ? jsonNumber(*f.nodata).c_str() : "null");
  std::printf("\"units\": {\"horizontal\": %s, \"vertical\": %s}, ",
              jsonStringOrNull(horizontalUnit(f.geo)).c_str(),
              jsonStringOrNull(f.zUnitName).c_str());
  std::printf("\"z_scale\": %.17g, ", f.zScale);
  std::printf("\"z_min\": %.9g, \"z_max\": %.9g, \"voids\": %zu}\n", s.zMinM, s.zMaxM, s.voids);
}

void printText(const aal::Heightfield& f, const aal::DemSummary& s) {
  std::printf("file       %s\n", f.source.c_str());
  std::printf("format     %s (GDAL driver %s)\n", f.format.c_str(), f.driver.c_str());
  std::printf("size       %d x %d (%zu texels)\n", f.width, f.height, f.texelCount());
  std::string crs = crsName(f.geo.crs);
  if (!f.geo.crsName.empty()) crs += ", " + f.geo.crsName;
  if (f.geo.epsg > 0) crs += " (EPSG:" + std::to_string(f.geo.epsg) + ")";
  if (f.geo.crs != aal::CrsKind::None) crs += ", in " + horizontalUnit(f.geo);
  std::printf("crs        %s\n", crs.c_str());
  if (f.rowCellSizeXM.empty()) {
    std::printf("cell size  x %.4f m, y %.4f m\n", f.cellSizeXM, f.cellSizeYM);
  } else {
    std::printf("cell size  x %.4f m at the centre row (%.4f .. %.4f m over the rows), y %.4f m\n",
                f.cellSizeXM, s.rowCellSizeXMinM, s.rowCellSizeXMaxM, f.cellSizeYM);
  }
  if (f.geo.hasCenter) {
    std::printf("centre     lat %.6f, lon %.6f (WGS84 degrees)\n", f.geo.centerLatDeg,
                f.geo.centerLonDeg);
  } else {
    std::printf("centre     unknown\n");
  }
  std::printf("heights    %.3f .. %.3f m (z scale %g%s)\n", s.zMinM, s.zMaxM, f.zScale,
              f.zUnitName.empty() ? "" : (", file unit " + f.zUnitName).c_str());
  if (f.nodata) std::printf("nodata     %s\n", jsonNumber(*f.nodata).c_str());
  std::printf("voids      %zu texels (%.3f%%), filled with the nearest valid height\n", s.voids,
              100.0 * static_cast<double>(s.voids) / f.texelCount());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app(
      "Prints what aperture reads from a DEM: format, size, CRS, metric cell size,\n"
      "geographic centre, height range and void count.\n\n" +
          aal::demFormatsHelp(),
      "aal-info");
  Options o;
  app.add_option("DEM", o.dem, "elevation file")->required();
  app.add_flag("--json", o.json,
               "print one JSON object with the keys format, driver, width, height, crs, "
               "crs_name, epsg, cell_size_m [x, y], center_lat, center_lon, nodata, units "
               "{horizontal, vertical}, z_scale, z_min, z_max, voids");
  // Unchecked by the parser: loadDem's checks say what is wrong.
  aal::addDemUnitsOptions(app, o.units, /*checked=*/false);

  return aal::runTool(app, argc, argv, [&] {
    aal::DemLoadOptions options;
    aal::applyDemUnits(o.units, options);
    options.warn = [](const std::string& message) {
      std::fprintf(stderr, "aal-info: warning: %s\n", message.c_str());
    };
    // A band of rows at a time: aal-info needs no memory for the whole DEM.
    const aal::DemSource source(o.dem, options);
    const aal::Heightfield field = aal::demGeometry(source, options);
    const aal::DemSummary summary = aal::summarizeDem(source, field);
    if (o.json) {
      printJson(field, summary);
    } else {
      printText(field, summary);
    }
    return aal::kExitOk;
  });
}
