#include "aperture/terrain/reference/color_ramp.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numeric>
#include <sstream>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/input_file.h"

namespace aal {

namespace {

// A number that fills the whole token; std::nullopt otherwise.
std::optional<double> number(const std::string& token) {
  if (token.empty()) return std::nullopt;
  const char* begin = token.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  if (end == begin || *end != '\0' || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string trimmed(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return {};
  const size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

}  // namespace

ColorRamp parseColorRamp(std::istream& in, const std::string& name) {
  ColorRamp ramp;
  std::string line;
  int lineNumber = 0;
  while (std::getline(in, line)) {
    ++lineNumber;
    const std::string text = trimmed(line);
    if (text.empty() || text[0] == '#') continue;
    std::string spaced = text;
    std::replace_if(
        spaced.begin(), spaced.end(), [](char c) { return c == ',' || c == ':' || c == '\t'; },
        ' ');
    std::istringstream fields(spaced);
    std::vector<std::string> tokens;
    for (std::string t; fields >> t;) tokens.push_back(t);
    auto bad = [&](const std::string& why) {
      return InputError(name + ":" + std::to_string(lineNumber) + ": " + why + ", got '" + text +
                        "'");
    };
    if (tokens.size() != 4 && tokens.size() != 5) {
      throw bad("expected 'elevation R G B [A]' (colour names are not supported)");
    }
    ColorRampEntry e;
    std::string head = tokens[0];
    std::transform(head.begin(), head.end(), head.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const bool nodata = head == "nv" || head == "nodata";
    if (!nodata) {
      e.percent = head.back() == '%';
      if (e.percent) head.pop_back();
      const std::optional<double> v = number(head);
      if (!v) throw bad("the elevation must be a number, a percentage like 50% or nv");
      if (e.percent && (*v < 0 || *v > 100)) throw bad("a percentage must be in [0, 100]");
      e.value = *v;
    }
    for (size_t c = 1; c < tokens.size(); ++c) {
      const std::optional<double> v = number(tokens[c]);
      if (!v || *v < 0 || *v > 255) throw bad("colour values must be numbers in [0, 255]");
      e.rgba[static_cast<int>(c - 1)] = static_cast<float>(*v);
    }
    if (nodata) {
      ramp.nodata = e.rgba;
    } else {
      ramp.entries.push_back(e);
    }
  }
  if (ramp.entries.empty()) {
    throw InputError(name + ": a colour ramp needs at least one 'elevation R G B [A]' line");
  }
  return ramp;
}

ColorRamp readColorRamp(const std::string& path) {
  // Capped, and only a regular file: `--color-relief /dev/zero` read without end.
  std::istringstream in(readTextInput(path, "colour ramp"));
  return parseColorRamp(in, path);
}

const std::vector<std::string>& builtinPaletteNames() {
  static const std::vector<std::string> names = {"hypsometric", "earth"};
  return names;
}

ColorRamp builtinPalette(const std::string& name) {
  // Hypsometric tints after the classic atlas scheme (Imhof, "Cartographic
  // Relief Presentation", 1965): lowland greens, yellow-browns, rock, snow.
  static const std::map<std::string, std::string> palettes = {
      {"hypsometric",
       "0% 60 130 75\n15% 110 165 90\n35% 215 210 135\n55% 195 150 90\n75% 150 110 85\n"
       "90% 190 180 170\n100% 250 250 250\n"},
      {"earth", "0% 120 150 95\n50% 205 185 140\n100% 240 235 225\n"},
  };
  const auto it = palettes.find(name);
  if (it == palettes.end()) {
    std::string known;
    for (const std::string& n : builtinPaletteNames()) known += (known.empty() ? "" : ", ") + n;
    throw InputError("--palette " + name + ": unknown palette (known: " + known + ")");
  }
  std::istringstream in(it->second);
  return parseColorRamp(in, "palette " + name);
}

ResolvedColorRamp resolveColorRamp(const ColorRamp& ramp, double zMin, double zMax) {
  std::vector<std::pair<double, glm::vec4>> entries;
  for (const ColorRampEntry& e : ramp.entries) {
    entries.emplace_back(e.percent ? zMin + (zMax - zMin) * e.value / 100.0 : e.value, e.rgba);
  }
  std::stable_sort(entries.begin(), entries.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  ResolvedColorRamp out;
  for (const auto& [z, c] : entries) {
    out.heights.push_back(z);
    out.rgba.push_back(c);
  }
  out.nodata = ramp.nodata;
  return out;
}

glm::vec4 rampColor(const ResolvedColorRamp& ramp, double z) {
  const auto& h = ramp.heights;
  if (z <= h.front()) return ramp.rgba.front();
  if (z >= h.back()) return ramp.rgba.back();
  const size_t i = static_cast<size_t>(std::upper_bound(h.begin(), h.end(), z) - h.begin());
  const double span = h[i] - h[i - 1];
  const float t = span > 0 ? static_cast<float>((z - h[i - 1]) / span) : 1.0f;
  return ramp.rgba[i - 1] + (ramp.rgba[i] - ramp.rgba[i - 1]) * t;
}

}  // namespace aal
