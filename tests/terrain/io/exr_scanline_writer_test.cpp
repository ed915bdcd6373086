// ExrScanlineWriter against OpenEXR's C++ reader: every compression, halves
// (against Imath's conversion) and floats, noise (RLE gains little or
// nothing: chunks stored raw) and runs (compressible), widths down to one
// texel, heights that end mid-chunk.
#include <gtest/gtest.h>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "aperture/terrain/io/exr_scanline_writer.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

constexpr std::array<const char*, 4> kChannels = {"R", "G", "B", "A"};

// Texels of width x height x 4 floats: random (noise in every bit the
// halves keep), or runs of a value that changes every 37 components.
std::vector<float> texels(int width, int height, bool noise) {
  std::vector<float> data(static_cast<size_t>(width) * height * 4);
  std::mt19937 random(7);
  std::uniform_real_distribution<float> uniform(-4.0f, 4.0f);
  for (size_t i = 0; i < data.size(); ++i) {
    data[i] = noise ? uniform(random) : static_cast<float>(i / 37) * 0.37f;
  }
  return data;
}

// What the file should hold: halves (Imath's conversion) or the floats, as
// bytes.
std::vector<uint8_t> stored(const std::vector<float>& data, bool halfFloat) {
  std::vector<uint8_t> bytes(data.size() * (halfFloat ? 2 : 4));
  for (size_t i = 0; i < data.size(); ++i) {
    if (halfFloat) {
      const uint16_t bits = Imath::half(data[i]).bits();
      std::memcpy(bytes.data() + 2 * i, &bits, 2);
    } else {
      std::memcpy(bytes.data() + 4 * i, &data[i], 4);
    }
  }
  return bytes;
}

// The file's pixels, interleaved in kChannels order, as stored.
std::vector<uint8_t> readBack(const std::string& path, bool halfFloat, int& width, int& height) {
  Imf::InputFile file(path.c_str());
  const Imath::Box2i window = file.header().dataWindow();
  width = window.max.x - window.min.x + 1;
  height = window.max.y - window.min.y + 1;
  const size_t component = halfFloat ? 2 : 4;
  std::vector<uint8_t> data(static_cast<size_t>(width) * height * 4 * component);
  Imf::FrameBuffer frame;
  for (size_t c = 0; c < 4; ++c) {
    frame.insert(kChannels[c], Imf::Slice(halfFloat ? Imf::HALF : Imf::FLOAT,
                                          reinterpret_cast<char*>(data.data() + c * component),
                                          4 * component, 4 * component * width));
  }
  file.setFrameBuffer(frame);
  file.readPixels(window.min.y, window.max.y);
  return data;
}

struct Case {
  MapCompression compression;
  bool halfFloat, noise;
  int width, height, blockRows;
};

TEST(ExrScanlineWriter, WritesWhatOpenExrReadsBackBitForBit) {
  test::TempDir dir;
  int index = 0;
  for (const MapCompression compression :
       {MapCompression::Rle, MapCompression::Zip, MapCompression::None}) {
    for (const bool halfFloat : {true, false}) {
      for (const bool noise : {true, false}) {
        for (const auto& [width, height, blockRows] :
             {std::array<int, 3>{1, 1, 16}, std::array<int, 3>{1, 53, 16},
              std::array<int, 3>{300, 45, 32}, std::array<int, 3>{129, 70, 48}}) {
          const std::string path = (dir.path() / (std::to_string(index++) + ".exr")).string();
          const std::vector<float> data = texels(width, height, noise);
          {
            ExrScanlineWriter writer(path, width, height, kChannels, halfFloat, compression,
                                     {{"aal:version", 3}, {"aal:method", std::string("sweep")}});
            for (int y = 0; y < height; y += blockRows) {
              const int end = std::min(height, y + blockRows);
              writer.writeRows(data.data() + static_cast<size_t>(y) * width * 4, y, end);
            }
            writer.finish();
          }
          const std::string what = std::to_string(int(compression)) + " half " +
                                   std::to_string(halfFloat) + " noise " + std::to_string(noise) +
                                   " " + std::to_string(width) + "x" + std::to_string(height);
          int w = 0, h = 0;
          const std::vector<uint8_t> back = readBack(path, halfFloat, w, h);
          EXPECT_EQ(w, width) << what;
          EXPECT_EQ(h, height) << what;
          EXPECT_EQ(back, stored(data, halfFloat)) << what;
          Imf::InputFile file(path.c_str());
          EXPECT_EQ(file.header().compression(),
                    compression == MapCompression::Rle   ? Imf::RLE_COMPRESSION
                    : compression == MapCompression::Zip ? Imf::ZIP_COMPRESSION
                                                         : Imf::NO_COMPRESSION)
              << what;
          const auto* version = file.header().findTypedAttribute<Imf::IntAttribute>("aal:version");
          ASSERT_TRUE(version) << what;
          EXPECT_EQ(version->value(), 3);
          const auto* method = file.header().findTypedAttribute<Imf::StringAttribute>("aal:method");
          ASSERT_TRUE(method) << what;
          EXPECT_EQ(method->value(), "sweep");
        }
      }
    }
  }
}

TEST(ExrScanlineWriter, RowsOutOfOrderOrPartialChunksAreRefused) {
  test::TempDir dir;
  const std::string path = (dir.path() / "a.exr").string();
  const std::vector<float> data = texels(8, 40, false);
  ExrScanlineWriter writer(path, 8, 40, kChannels, true, MapCompression::Zip, {});
  EXPECT_EQ(writer.rowsPerChunk(), 16);
  EXPECT_THROW(writer.writeRows(data.data(), 16, 32), std::logic_error);  // skips rows 0..15
  EXPECT_THROW(writer.writeRows(data.data(), 0, 8), std::logic_error);    // half a chunk
  writer.writeRows(data.data(), 0, 32);
  EXPECT_THROW(writer.finish(), std::logic_error);  // rows 32..39 missing
}

TEST(ExrScanlineWriter, AnUnwritablePathIsARuntimeErrorNamingIt) {
  const std::string path = "/nonexistent-folder/a.exr";
  try {
    ExrScanlineWriter writer(path, 4, 4, kChannels, true, MapCompression::Rle, {});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace aal
