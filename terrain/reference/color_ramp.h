// Colour ramps for colour relief (aal-relief --color-relief, --palette): the
// text format of `gdaldem color-relief` and built-in hypsometric palettes.
//
// A ramp file has one entry per line: "elevation R G B [A]" with colour
// values 0..255, separated by spaces, tabs, commas or colons; the elevation
// may be a percentage of the DEM's height range ("50%": 0% is the lowest
// non-void height, 100% the highest) or "nv" (the colour of nodata). Blank
// lines and lines starting with '#' are skipped. Heights between entries are
// interpolated linearly, heights beyond the ends take the end's colour
// (gdaldem's default, without -exact_color_entry / -nearest_color_entry).
#pragma once

#include <istream>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

namespace aal {

struct ColorRampEntry {
  double value = 0;  // metres, or percent when `percent`
  bool percent = false;
  glm::vec4 rgba{0, 0, 0, 255};  // 0..255
};

struct ColorRamp {
  std::vector<ColorRampEntry> entries;  // in file order
  std::optional<glm::vec4> nodata;      // the "nv" entry
};

// Throws InputError "NAME:LINE: why" for a malformed line, and "NAME: ..."
// for a ramp without entries. `name` is the file's name for messages.
ColorRamp parseColorRamp(std::istream& in, const std::string& name);
// Reads a ramp file (terrain/io/input_file.h, readTextInput: a regular file
// of at most 16 MiB; a UTF-8 byte order mark at its start is skipped);
// throws InputError naming the file when it is missing, a folder, not a
// regular file (a FIFO, /dev/zero), over the cap, or cannot be read or
// parsed.
ColorRamp readColorRamp(const std::string& path);

// The built-in palettes by name ("hypsometric", "earth"), in percent of the
// height range; throws InputError naming the known ones for another name.
ColorRamp builtinPalette(const std::string& name);
const std::vector<std::string>& builtinPaletteNames();

// A ramp with its percentages turned into heights for a DEM whose non-void
// heights span [zMin, zMax], sorted by height.
struct ResolvedColorRamp {
  std::vector<double> heights;
  std::vector<glm::vec4> rgba;
  std::optional<glm::vec4> nodata;
};
ResolvedColorRamp resolveColorRamp(const ColorRamp& ramp, double zMin, double zMax);

// The colour (0..255 RGBA) of height z: linear between the entries around
// it, the end entry's colour beyond either end.
glm::vec4 rampColor(const ResolvedColorRamp& ramp, double z);

}  // namespace aal
