#include "ascii_grid_reader.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "errors.h"

namespace aal {

namespace {

constexpr const char* kKeys[] = {"ncols",     "nrows",    "xllcorner", "xllcenter", "yllcorner",
                                 "yllcenter", "cellsize", "dx",        "dy",        "nodata_value"};

std::string lower(std::string_view text) {
  std::string result(text);
  std::transform(result.begin(), result.end(), result.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return result;
}

// Whitespace-separated tokens of a text, with line numbers for messages.
class Tokens {
 public:
  explicit Tokens(std::string_view text) : text_(text) {}

  // The next token without consuming it; empty at the end.
  std::string_view peek() {
    skipSpace();
    size_t end = position_;
    while (end < text_.size() && !isSpace(text_[end])) ++end;
    return text_.substr(position_, end - position_);
  }
  std::string_view next() {
    const std::string_view token = peek();
    position_ += token.size();
    return token;
  }
  size_t remainingBytes() const { return text_.size() - position_; }
  int line() const {
    return 1 + static_cast<int>(std::count(text_.begin(), text_.begin() + position_, '\n'));
  }

 private:
  static bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
  void skipSpace() {
    while (position_ < text_.size() && isSpace(text_[position_])) ++position_;
  }
  std::string_view text_;
  size_t position_ = 0;
};

std::optional<double> parseDouble(std::string_view token) {
  if (!token.empty() && token[0] == '+') token.remove_prefix(1);
  double value = 0;
  const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (error != std::errc() || end != token.data() + token.size() || token.empty()) {
    return std::nullopt;
  }
  return value;
}

bool isHeaderKey(std::string_view token) {
  if (token.empty() || !std::isalpha(static_cast<unsigned char>(token[0]))) return false;
  const std::string key = lower(token);
  return key.rfind("nan", 0) != 0 && key.rfind("inf", 0) != 0;  // nan/inf are samples
}

struct Header {
  std::map<std::string, double> values;

  bool has(const char* key) const { return values.count(key) != 0; }
  double get(const char* key) const { return values.at(key); }
};

Header readHeader(const std::string& path, Tokens& tokens) {
  Header header;
  while (isHeaderKey(tokens.peek())) {
    const int line = tokens.line();
    const std::string key = lower(tokens.next());
    if (std::find(std::begin(kKeys), std::end(kKeys), key) == std::end(kKeys)) {
      throw InputError(path + ": unknown header entry '" + key + "' on line " +
                       std::to_string(line));
    }
    if (header.has(key.c_str())) {
      throw InputError(path + ": header entry '" + key + "' appears twice");
    }
    const std::string_view text = tokens.next();
    const std::optional<double> value = parseDouble(text);
    if (!value || (!std::isfinite(*value) && key != "nodata_value")) {
      throw InputError(path + ": header entry '" + key + "' has non-numeric value '" +
                       std::string(text) + "' on line " + std::to_string(line));
    }
    header.values[key] = *value;
  }
  return header;
}

void require(const std::string& path, const Header& header, const char* key,
             const char* alternative = nullptr) {
  if (header.has(key) || (alternative && header.has(alternative))) return;
  throw InputError(path + ": header lacks '" + key + "'" +
                   (alternative ? std::string(" or '") + alternative + "'" : std::string()));
}

int64_t integerEntry(const std::string& path, const Header& header, const char* key) {
  const double value = header.get(key);
  if (value != std::trunc(value) || std::abs(value) > 1e15) {
    throw InputError(path + ": header entry '" + key + "' must be a whole number");
  }
  return static_cast<int64_t>(value);
}

// Cell sizes in x and y, CRS units.
std::pair<double, double> cellSizes(const std::string& path, const Header& header) {
  const bool square = header.has("cellsize");
  if (square && (header.has("dx") || header.has("dy"))) {
    throw InputError(path + ": header has both 'cellsize' and 'dx'/'dy'");
  }
  if (!square && !(header.has("dx") && header.has("dy"))) {
    throw InputError(path + ": header lacks 'cellsize' (or both 'dx' and 'dy')");
  }
  const double x = square ? header.get("cellsize") : header.get("dx");
  const double y = square ? header.get("cellsize") : header.get("dy");
  if (!(x > 0.0) || !(y > 0.0)) {
    throw InputError(path + ": inconsistent georeferencing: cell size must be positive");
  }
  return {x, y};
}

// What a WKT .prj says: geographic or projected, unit and EPSG code.
void applyPrj(const std::string& wkt, GeoReference& geo) {
  const std::string upper = [&] {
    std::string u = wkt;
    std::transform(u.begin(), u.end(), u.begin(),
                   [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
    return u;
  }();
  const size_t start = upper.find_first_not_of(" \t\r\n");
  const bool geographic = start != std::string::npos && (upper.compare(start, 6, "GEOGCS") == 0 ||
                                                         upper.compare(start, 7, "GEOGCRS") == 0);
  geo.crs = geographic ? CrsKind::Geographic : CrsKind::Projected;
  const size_t authority = upper.rfind("AUTHORITY[\"EPSG\",");
  if (authority != std::string::npos) {
    size_t digit = upper.find_first_of("0123456789", authority);
    int code = 0;
    while (digit < upper.size() && std::isdigit(static_cast<unsigned char>(upper[digit])) &&
           code < 1000000) {
      code = code * 10 + (upper[digit++] - '0');
    }
    geo.epsg = code;
  }
  if (!geographic) {
    const size_t unit = upper.rfind("UNIT[");
    if (unit != std::string::npos) {
      const size_t comma = upper.find(',', unit);
      if (comma != std::string::npos) {
        const size_t end = upper.find_first_of(",]", comma + 1);
        const std::optional<double> factor =
            parseDouble(std::string_view(upper).substr(comma + 1, end - comma - 1));
        if (factor && *factor > 0.0 && std::isfinite(*factor)) geo.linearUnitM = *factor;
      }
    }
  }
}

GeoReference georeference(const std::string& path, const Header& header, int64_t rows,
                          const std::optional<std::string>& prjText,
                          const DemLoadOptions& options) {
  const auto [cellX, cellY] = cellSizes(path, header);
  if (header.has("xllcorner") && header.has("xllcenter")) {
    throw InputError(path + ": header has both 'xllcorner' and 'xllcenter'");
  }
  if (header.has("yllcorner") && header.has("yllcenter")) {
    throw InputError(path + ": header has both 'yllcorner' and 'yllcenter'");
  }
  GeoReference geo;
  geo.stepX = cellX;
  geo.stepY = cellY;
  // Corners are the outer edge of the south-west cell; centres its centre.
  const double westX =
      header.has("xllcenter") ? header.get("xllcenter") : header.get("xllcorner") + 0.5 * cellX;
  const double southY =
      header.has("yllcenter") ? header.get("yllcenter") : header.get("yllcorner") + 0.5 * cellY;
  geo.originX = westX;
  geo.originY = southY + static_cast<double>(rows - 1) * cellY;
  if (prjText) {
    applyPrj(*prjText, geo);
  } else {
    geo.crs = CrsKind::Projected;
    if (std::max(cellX, cellY) < 0.01 && options.warn) {
      options.warn(path + ": cell size " + std::to_string(cellX) +
                   " looks like degrees, but there is no .prj to say so; taken as metres "
                   "(add a .prj or give --cell-size)");
    }
  }
  return geo;
}

}  // namespace

RawDem parseAsciiGrid(const std::string& path, std::string_view text,
                      const std::optional<std::string>& prjText, const DemLoadOptions& options) {
  Tokens tokens(text);
  const Header header = readHeader(path, tokens);
  require(path, header, "ncols");
  require(path, header, "nrows");
  require(path, header, "xllcorner", "xllcenter");
  require(path, header, "yllcorner", "yllcenter");
  const int64_t columns = integerEntry(path, header, "ncols");
  const int64_t rows = integerEntry(path, header, "nrows");
  checkDemSize(path, columns, rows, options.maxTexels);
  const size_t count = static_cast<size_t>(columns) * static_cast<size_t>(rows);
  // Each sample takes at least one character and a separator: refuse before
  // allocating when the text cannot hold them.
  if (tokens.remainingBytes() + 1 < 2 * count) {
    throw InputError(path + ": truncated: " + std::to_string(tokens.remainingBytes()) +
                     " bytes cannot hold " + std::to_string(columns) + " x " +
                     std::to_string(rows) + " samples");
  }
  RawDem dem;
  dem.format = "ESRI ASCII grid";
  dem.sampleType = "text";
  dem.geo = georeference(path, header, rows, prjText, options);
  // A plain flag and value: GCC 12 warns (wrongly) about an optional here.
  const bool hasNodata = header.has("nodata_value");
  const double nodata = hasNodata ? header.get("nodata_value") : 0.0;
  dem.allocate(static_cast<int>(columns), static_cast<int>(rows));
  for (size_t i = 0; i < count; ++i) {
    const std::string_view token = tokens.next();
    const size_t row = i / static_cast<size_t>(columns), column = i % static_cast<size_t>(columns);
    if (token.empty()) {
      throw InputError(path + ": truncated: " + std::to_string(i) + " samples of " +
                       std::to_string(count) + " (row " + std::to_string(row + 1) +
                       " is incomplete)");
    }
    const std::optional<double> value = parseDouble(token);
    if (!value) {
      throw InputError(path + ": non-numeric sample '" + std::string(token.substr(0, 32)) +
                       "' at row " + std::to_string(row + 1) + ", column " +
                       std::to_string(column + 1));
    }
    if (hasNodata &&
        (*value == nodata || static_cast<float>(*value) == static_cast<float>(nodata))) {
      dem.voidMask[i] = 1;
    } else {
      storeSample(dem, i, *value);
    }
  }
  if (!tokens.peek().empty()) {
    throw InputError(path + ": more samples than ncols x nrows = " + std::to_string(count) +
                     " (extra '" + std::string(tokens.peek().substr(0, 32)) + "' on line " +
                     std::to_string(tokens.line()) + ")");
  }
  return dem;
}

RawDem readAsciiGrid(const std::string& path, const DemLoadOptions& options) {
  const auto readText = [](const std::filesystem::path& file) -> std::optional<std::string> {
    std::ifstream in(file, std::ios::binary);
    if (!in) return std::nullopt;
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) return std::nullopt;
    return text.str();
  };
  const std::optional<std::string> text = readText(path);
  if (!text) throw InputError(path + ": cannot read");
  std::filesystem::path prj = path;
  prj.replace_extension(".prj");
  std::error_code error;
  const std::optional<std::string> prjText =
      std::filesystem::is_regular_file(prj, error) ? readText(prj) : std::nullopt;
  return parseAsciiGrid(path, *text, prjText, options);
}

}  // namespace aal
