#include "aperture_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <OpenImageIO/imageio.h>

#include "atomic_file.h"
#include "errors.h"

namespace aal {

float ApertureMap::visibleFraction(size_t texel) const {
  return 1.0f - std::cos(texels[4 * texel + 3]);
}

std::string heightfieldChecksum(const Heightfield& field) {
  uint64_t hash = 0xcbf29ce484222325ull;
  auto mix = [&hash](const void* data, size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < bytes; ++i) {
      hash ^= p[i];
      hash *= 0x100000001b3ull;
    }
  };
  mix(&field.width, sizeof field.width);
  mix(&field.height, sizeof field.height);
  mix(field.z.data(), field.z.size() * sizeof(float));
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

void writeApertureMap(const std::string& path, const ApertureMap& map, bool halfFloat) {
  AtomicOutput output(path);
  OIIO::ImageSpec spec(map.width, map.height, 4,
                       halfFloat ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"R", "G", "B", "A"};
  spec.attribute("compression", "zip");
  const ApertureMapInfo& i = map.info;
  spec.attribute("aal:version", i.version);
  spec.attribute("aal:azimuths", i.azimuths);
  spec.attribute("aal:method", i.method);
  spec.attribute("aal:cellSizeX", static_cast<float>(i.cellSizeX));
  spec.attribute("aal:cellSizeY", static_cast<float>(i.cellSizeY));
  spec.attribute("aal:zScale", static_cast<float>(i.zScale));
  spec.attribute("aal:source", i.source);
  spec.attribute("aal:sourceSize",
                 std::to_string(i.sourceWidth) + "x" + std::to_string(i.sourceHeight));
  spec.attribute("aal:sourceChecksum", i.sourceChecksum);
  spec.attribute("aal:edge", i.edge);
  spec.attribute("aal:curvature", i.curvature ? 1 : 0);
  spec.attribute("aal:refraction", static_cast<float>(i.refraction));
  spec.attribute("aal:maxDistance", static_cast<float>(i.maxDistanceM));

  auto out = OIIO::ImageOutput::create(output.temporaryPath().string());
  if (!out || !out->open(output.temporaryPath().string(), spec)) {
    throw std::runtime_error("cannot write aperture map " + path + ": " + OIIO::geterror());
  }
  // In blocks of rows, so that converting to half never copies the whole map.
  constexpr int kRows = 64;
  for (int y = 0; y < map.height; y += kRows) {
    const int end = std::min(map.height, y + kRows);
    const float* rows = map.texels.data() + static_cast<size_t>(y) * map.width * 4;
    if (!out->write_scanlines(y, end, 0, OIIO::TypeDesc::FLOAT, rows)) {
      throw std::runtime_error("cannot write aperture map " + path + ": " + out->geterror());
    }
  }
  if (!out->close()) {
    throw std::runtime_error("cannot write aperture map " + path + ": " + out->geterror());
  }
  output.commit();
}

namespace {

std::unique_ptr<OIIO::ImageInput> openApertureMap(const std::string& path,
                                                  ApertureMapHeader& header) {
  if (!std::filesystem::exists(path)) throw InputError("aperture map " + path + " does not exist");
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw InputError("cannot read aperture map " + path + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.nchannels != 4) {
    throw InputError("aperture map " + path + " has " + std::to_string(spec.nchannels) +
                     " channels, expected 4 (bent normal RGB + arc length A)");
  }
  if (!spec.find_attribute("aal:version")) {
    throw InputError("aperture map " + path + " has no aal: attributes: not made by aal-bake");
  }
  header.width = spec.width;
  header.height = spec.height;
  ApertureMapInfo& i = header.info;
  i.version = spec.get_int_attribute("aal:version");
  i.azimuths = spec.get_int_attribute("aal:azimuths");
  i.method = spec.get_string_attribute("aal:method");
  i.cellSizeX = spec.get_float_attribute("aal:cellSizeX");
  i.cellSizeY = spec.get_float_attribute("aal:cellSizeY");
  i.zScale = spec.get_float_attribute("aal:zScale", 1.0f);
  i.source = spec.get_string_attribute("aal:source");
  i.sourceChecksum = spec.get_string_attribute("aal:sourceChecksum");
  i.edge = spec.get_string_attribute("aal:edge", "open");
  i.curvature = spec.get_int_attribute("aal:curvature") != 0;
  i.refraction = spec.get_float_attribute("aal:refraction");
  i.maxDistanceM = spec.get_float_attribute("aal:maxDistance");
  if (std::sscanf(spec.get_string_attribute("aal:sourceSize").c_str(), "%dx%d", &i.sourceWidth,
                  &i.sourceHeight) != 2) {
    throw InputError("aperture map " + path + " has a malformed aal:sourceSize attribute");
  }
  return in;
}

}  // namespace

ApertureMap readApertureMap(const std::string& path) {
  ApertureMapHeader header;
  auto in = openApertureMap(path, header);
  ApertureMap map;
  map.width = header.width;
  map.height = header.height;
  map.info = header.info;
  map.texels.resize(map.texelCount() * 4);
  if (!in->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, map.texels.data())) {
    throw InputError("cannot read aperture map " + path +
                     " (truncated or corrupt): " + in->geterror());
  }
  return map;
}

struct ApertureMapReader::Impl {
  std::unique_ptr<OIIO::ImageInput> input;
};

ApertureMapReader::ApertureMapReader(const std::string& path) : path_(path), impl_(new Impl) {
  try {
    impl_->input = openApertureMap(path, header_);
  } catch (...) {
    delete impl_;
    throw;
  }
}

ApertureMapReader::~ApertureMapReader() {
  delete impl_;
}

void ApertureMapReader::readHalfRows(int firstRow, int endRow, void* destination) {
  if (!impl_->input->read_scanlines(0, 0, firstRow, endRow, 0, 0, 4, OIIO::TypeDesc::HALF,
                                    destination) ||
      impl_->input->has_error()) {
    throw InputError("cannot read aperture map " + path_ +
                     " (truncated or corrupt): " + impl_->input->geterror());
  }
}

void checkApertureMatchesDem(const ApertureMapHeader& map, const std::string& mapPath,
                             const Heightfield& field, const std::string& demPath) {
  const std::string pair = "aperture map " + mapPath + " does not belong to DEM " + demPath;
  if (map.width != field.width || map.height != field.height) {
    throw InputError(pair + ": map is " + std::to_string(map.width) + "x" +
                     std::to_string(map.height) + ", DEM is " + std::to_string(field.width) + "x" +
                     std::to_string(field.height));
  }
  if (map.info.sourceChecksum != heightfieldChecksum(field)) {
    throw InputError(pair + ": it was baked from other heights (" + map.info.source +
                     "); bake it again with aal-bake");
  }
}

void checkApertureMatchesDem(const ApertureMap& map, const std::string& mapPath,
                             const Heightfield& field, const std::string& demPath) {
  checkApertureMatchesDem(ApertureMapHeader{map.width, map.height, map.info}, mapPath, field,
                          demPath);
}

}  // namespace aal
