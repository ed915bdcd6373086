// Directional horizons (terrain/io/horizon_map.h) and the horizon shading mode's
// sun term (terrain/light/shading.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

#include <sys/stat.h>
#include <unistd.h>

#include <glm/geometric.hpp>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/terrain/light/caps.h"
#include "aperture/terrain/light/shading.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(HorizonMap, CodesKeepTheElevationToHalfAStepFinestNearTheHorizontal) {
  for (double e = -0.03; e < 1.57; e += 1e-4) {
    const uint8_t c = encodeHorizon(float(e));
    const double step =
        decodeHorizon(uint8_t(std::min(255, c + 1))) - decodeHorizon(uint8_t(std::max(0, c - 1)));
    EXPECT_LE(std::abs(decodeHorizon(c) - e), 0.5 * step + 1e-6) << e;
  }
  // Steps of 0.11 degrees at the horizontal, 0.26 at 10, 0.43 at 30.
  const auto stepAt = [](double deg) {
    const uint8_t c = encodeHorizon(float(deg * kPi / 180));
    return (decodeHorizon(uint8_t(c + 1)) - decodeHorizon(c)) * 180 / kPi;
  };
  EXPECT_LT(stepAt(0), 0.12);
  EXPECT_LT(stepAt(10), 0.27);
  EXPECT_LT(stepAt(30), 0.45);
  // Below the range (open ground, no terrain ahead): the minimum.
  EXPECT_EQ(encodeHorizon(-1.0f), 0);
  EXPECT_EQ(encodeHorizon(-1.5707963f), 0);
  EXPECT_EQ(encodeHorizon(std::nanf("")), 0);
  EXPECT_EQ(encodeHorizon(2.0f), 255);
  EXPECT_FLOAT_EQ(decodeHorizon(0), kHorizonMinRad);
  EXPECT_FLOAT_EQ(decodeHorizon(255), kHorizonMaxRad);
}

// 4-bit codes: the nearest of 16 levels in elevation, to 45 degrees.
TEST(HorizonMap, FourBitCodesKeepTheNearestLevelUpTo45Degrees) {
  for (double e = -0.03; e < 1.57; e += 1e-4) {
    const uint8_t c = encodeHorizon(float(e), 4);
    ASSERT_LE(c, 15);
    const double kept = std::min(e, double(kHorizon4BitMaxRad));
    for (int other = 0; other < 16; ++other) {
      EXPECT_LE(std::abs(decodeHorizon(c, 4) - kept),
                std::abs(decodeHorizon(uint8_t(other), 4) - kept) + 1e-6)
          << e << " took code " << int(c) << ", " << other << " is nearer";
    }
  }
  // Levels (degrees) -2, -1.19, 0.29, 2.20, 4.47, 7.05, 9.89, 12.98, ...,
  // 40.38, 45: 1.9 apart at the horizontal, 3.1 at 10, 4.6 at 40.
  const auto stepAt = [](double deg) {
    const uint8_t c = encodeHorizon(float(deg * kPi / 180), 4);
    return (decodeHorizon(uint8_t(c + 1), 4) - decodeHorizon(c, 4)) * 180 / kPi;
  };
  EXPECT_LT(stepAt(0), 2.0);
  EXPECT_LT(stepAt(10), 3.1);
  EXPECT_LT(stepAt(40), 4.63);
  EXPECT_EQ(encodeHorizon(-1.0f, 4), 0);
  EXPECT_EQ(encodeHorizon(std::nanf(""), 4), 0);
  EXPECT_EQ(encodeHorizon(1.0f, 4), 15);
  EXPECT_FLOAT_EQ(decodeHorizon(0, 4), kHorizonMinRad);
  EXPECT_FLOAT_EQ(decodeHorizon(15, 4), kHorizon4BitMaxRad);
  EXPECT_FLOAT_EQ(decodeHorizonUnorm(7.0f / 15.0f, 4), decodeHorizon(7, 4));
}

TEST(HorizonMap, AzimuthsBetweenStoredDirectionsInterpolateLinearly) {
  uint8_t codes[kHorizonDirections];
  for (int k = 0; k < kHorizonDirections; ++k) codes[k] = uint8_t(20 * k + 10);
  const float step = float(2 * kPi / kHorizonDirections);
  for (int k = 0; k < kHorizonDirections; ++k) {
    EXPECT_NEAR(horizonAtAzimuth(codes, kHorizonDirections, k * step), decodeHorizon(codes[k]),
                1e-6f);
    const int next = (k + 1) % kHorizonDirections;
    EXPECT_NEAR(horizonAtAzimuth(codes, kHorizonDirections, (k + 0.25f) * step),
                0.75f * decodeHorizon(codes[k]) + 0.25f * decodeHorizon(codes[next]), 1e-6f);
  }
  // Wraps around: -10 degrees is 350 degrees, between the last and the first.
  EXPECT_NEAR(horizonAtAzimuth(codes, kHorizonDirections, float(-10 * kPi / 180)),
              horizonAtAzimuth(codes, kHorizonDirections, float(350 * kPi / 180)), 1e-6f);
  EXPECT_NEAR(horizonAtAzimuth(codes, kHorizonDirections, float(2 * kPi)), decodeHorizon(codes[0]),
              1e-6f);
  // Sixteen directions: 22.5 degrees apart.
  uint8_t sixteen[16];
  for (int k = 0; k < 16; ++k) sixteen[k] = uint8_t(9 * k);
  EXPECT_NEAR(horizonAtAzimuth(sixteen, 16, float(3.5 * kPi / 8)),
              0.5f * (decodeHorizon(27) + decodeHorizon(36)), 1e-6f);
}

// The horizon at azimuth a from the pair (first, first + 1) on the device, as
// the shader reads it with the per-frame weights (horizonPairWeights): the
// pair's decoded horizons times their weights, in double precision here.
double horizonFromPair(const uint8_t* codes, int directions, float a, int bits, int first) {
  const std::array<float, 2> w = horizonPairWeights(directions, a, first);
  EXPECT_GE(w[0], 0.0f);
  EXPECT_GE(w[1], 0.0f);
  EXPECT_FLOAT_EQ(w[0] + w[1], 1.0f);
  return double(w[0]) * decodeHorizon(codes[first], bits) +
         double(w[1]) * decodeHorizon(codes[(first + 1) % directions], bits);
}

// For every azimuth of a dense sweep (a sun moving round, and a sun appearing
// there with no pair laid, or any other pair), horizonPairFor picks a pair
// whose weights give horizonAtAzimuth's horizon to float rounding where the
// sun lies within the pair's span, and the nearer direction's horizon
// within the margin outside it (a sun that stayed, hysteresis): never more
// than the margin's worth of interpolation away.
TEST(HorizonMap, ChosenPairGivesTheHorizonAtEveryAzimuth) {
  std::mt19937 rng(18);
  for (const int bits : {8, 4}) {
    for (const int directions : {8, 12, 16, 4}) {
      std::uniform_int_distribution<int> code(0, (1 << bits) - 1);
      uint8_t codes[kMaxHorizonDirections];
      for (uint8_t& c : codes) c = uint8_t(code(rng));
      const double step = 2 * kPi / directions;
      // The most the horizon changes over the margin: the largest
      // difference of neighbours times the margin.
      double steepest = 0;
      for (int k = 0; k < directions; ++k) {
        steepest = std::max(steepest, std::abs(double(decodeHorizon(codes[k], bits)) -
                                               decodeHorizon(codes[(k + 1) % directions], bits)));
      }
      int moving = -1, checked = 0, outside = 0;
      // Two turns and a half, from below zero (azimuths wrap).
      constexpr int kSamples = 50000;
      for (int i = 0; i <= kSamples; ++i) {
        const float a = float(-kPi + 5 * kPi * i / kSamples);
        moving = horizonPairFor(directions, a, moving);
        const int fresh = horizonPairFor(directions, a, -1);
        const int other = horizonPairFor(directions, a, (i * 7) % directions);
        double x = a / step;
        x -= directions * std::floor(x / directions);
        const auto stepsPast = [&](int first) {
          double past = x - first;
          return past - directions * std::floor(past / directions + 0.5);
        };
        // A fresh pick is the pair whose span holds the sun (to float rounding).
        ASSERT_GE(stepsPast(fresh), -1e-4) << directions << " at " << a;
        ASSERT_LE(stepsPast(fresh), 1 + 1e-4) << directions << " at " << a;
        for (const int first : {moving, fresh, other}) {
          ASSERT_TRUE(validHorizonPair(directions, first));
          const double past = stepsPast(first);
          ASSERT_GE(past, -kHorizonPairMargin - 1e-4) << directions << " at " << a;
          ASSERT_LE(past, 1 + kHorizonPairMargin + 1e-4) << directions << " at " << a;
          const double expected = horizonAtAzimuth(codes, directions, a, bits);
          const double got = horizonFromPair(codes, directions, a, bits, first);
          if (past >= 1e-4 && past <= 1 - 1e-4) {
            ASSERT_NEAR(got, expected, 2e-6) << bits << " bits, " << directions
                                             << " directions, azimuth " << a << ", pair " << first;
          } else {
            ++outside;
            ASSERT_NEAR(got, expected, kHorizonPairMargin * steepest + 2e-6)
                << bits << " bits, " << directions << " directions, azimuth " << a << ", pair "
                << first;
          }
          ++checked;
        }
      }
      EXPECT_EQ(checked, 3 * (kSamples + 1));
      EXPECT_GT(outside, 0) << "the hysteresis was exercised";
    }
  }
  EXPECT_THROW(horizonPairWeights(8, 0.1f, 8), std::invalid_argument);
  EXPECT_THROW(horizonPairWeights(8, 0.1f, -1), std::invalid_argument);
  EXPECT_FALSE(validHorizonPair(6, 0));
}

// Hysteresis: a sun resting on a stored direction, or jittering about it,
// keeps its pair; a sun going round changes it once per direction step,
// never back and forth.
TEST(HorizonMap, PairHoldsAtAStoredDirection) {
  for (const int directions : {4, 8, 12, 16}) {
    const double step = 2 * kPi / directions;
    for (int k = 0; k < directions; ++k) {
      // Direction k itself, and the points where horizonPairFor switches.
      for (const double at :
           {double(k), k + 1 + double(kHorizonPairMargin), k - double(kHorizonPairMargin)}) {
        for (const int start : {-1, (k + directions - 1) % directions, k}) {
          int first = start, changes = 0;
          for (int i = 0; i < 200; ++i) {
            const double jitter = (i % 2 ? 1 : -1) * 1e-4 * (1 + i % 7);
            const int next = horizonPairFor(directions, float((at + jitter) * step), first);
            changes += i > 0 && next != first;
            first = next;
          }
          EXPECT_LE(changes, 1) << directions << " directions, position " << at << ", from "
                                << start;
        }
      }
    }
    // One turn from mid-pair back to it: a pair per step and the first again.
    for (const int turn : {1, -1}) {
      int first = horizonPairFor(directions, float(0.5 * step), -1), changes = 0;
      constexpr int kSamples = 100000;
      for (int i = 1; i <= kSamples; ++i) {
        const int next =
            horizonPairFor(directions, float(0.5 * step + turn * 2 * kPi * i / kSamples), first);
        changes += next != first;
        first = next;
      }
      EXPECT_EQ(changes, directions) << directions << " directions, one turn";
    }
  }
  // The switch comes a margin past the pair's span (directions 3 and 4 of 8).
  const float step8 = float(2 * kPi / 8);
  EXPECT_EQ(horizonPairFor(8, (4 + 0.5f * kHorizonPairMargin) * step8, 3), 3);
  EXPECT_EQ(horizonPairFor(8, (4 + 1.5f * kHorizonPairMargin) * step8, 3), 4);
  EXPECT_EQ(horizonPairFor(8, (3 - 0.5f * kHorizonPairMargin) * step8, 3), 3);
  EXPECT_EQ(horizonPairFor(8, (3 - 1.5f * kHorizonPairMargin) * step8, 3), 2);
  // Across zero: the pair 7, 0 holds a sun just past east.
  EXPECT_EQ(horizonPairFor(8, 0.5f * kHorizonPairMargin * step8, 7), 7);
  EXPECT_EQ(horizonPairFor(8, -0.5f * step8, -1), 7);
}

TEST(HorizonMap, FilesRoundTripAndForeignOrTruncatedFilesAreRefused) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("aal-horizons-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  HorizonMap map;
  map.width = 5;
  map.height = 3;
  map.sourceChecksum = "r2-0123456789abcdef";
  for (int i = 0; i < map.width * map.height * kHorizonDirections; ++i) {
    map.codes.push_back(uint8_t(i * 7));
  }
  writeHorizonMap(dir / "h.bin", map);
  const HorizonMap read = readHorizonMap(dir / "h.bin");
  EXPECT_EQ(read.width, 5);
  EXPECT_EQ(read.height, 3);
  EXPECT_EQ(read.codes, map.codes);
  EXPECT_EQ(read.bits, 8);
  EXPECT_EQ(read.sourceChecksum, map.sourceChecksum);
  EXPECT_EQ(
      std::filesystem::file_size(dir / "h.bin"),
      std::string("aperture-horizons 4 5 3 8 8 r2-0123456789abcdef 0123456789abcdef\n").size() +
          map.codes.size());
  // Without the DEM's checksum there is nothing to check it against later.
  HorizonMap unchecked = map;
  unchecked.sourceChecksum.clear();
  EXPECT_THROW(writeHorizonMap(dir / "unchecked.bin", unchecked), std::invalid_argument);
  unchecked.sourceChecksum = "two words";
  EXPECT_THROW(writeHorizonMap(dir / "unchecked.bin", unchecked), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(dir / "unchecked.bin"));
  // Version 3 without its checksum is damaged, and so is version 4 without
  // the checksum of its codes.
  std::ofstream(dir / "nosum.bin") << "aperture-horizons 3 5 3 8 8\n";
  EXPECT_THROW(readHorizonMap(dir / "nosum.bin"), std::runtime_error);
  std::ofstream(dir / "nocodesum.bin") << "aperture-horizons 4 5 3 8 8 r2-0123456789abcdef\n";
  EXPECT_THROW(readHorizonMap(dir / "nocodesum.bin"), std::runtime_error);
  // Version 2 (before the checksum): read, the checksum unknown.
  {
    std::ofstream v2(dir / "v2.bin", std::ios::binary);
    v2 << "aperture-horizons 2 5 3 8 8\n";
    v2.write(reinterpret_cast<const char*>(map.codes.data()), std::streamsize(map.codes.size()));
  }
  const HorizonMap v2 = readHorizonMap(dir / "v2.bin");
  EXPECT_EQ(v2.codes, map.codes);
  EXPECT_TRUE(v2.sourceChecksum.empty());
  // Version 1 (before 4-bit codes): 8 bits, no bits field.
  {
    std::ofstream old(dir / "v1.bin", std::ios::binary);
    old << "aperture-horizons 1 5 3 8\n";
    old.write(reinterpret_cast<const char*>(map.codes.data()), std::streamsize(map.codes.size()));
  }
  const HorizonMap v1 = readHorizonMap(dir / "v1.bin");
  EXPECT_EQ(v1.bits, 8);
  EXPECT_EQ(v1.codes, map.codes);
  EXPECT_TRUE(v1.sourceChecksum.empty());
  // 4-bit codes, one per byte; a code above 15 is refused.
  HorizonMap four = map;
  four.bits = 4;
  for (uint8_t& c : four.codes) c &= 15;
  writeHorizonMap(dir / "four.bin", four);
  const HorizonMap readFour = readHorizonMap(dir / "four.bin");
  EXPECT_EQ(readFour.bits, 4);
  EXPECT_EQ(readFour.codes, four.codes);
  EXPECT_EQ(readFour.sourceChecksum, map.sourceChecksum);
  four.codes[3] = 16;
  EXPECT_THROW(writeHorizonMap(dir / "bad.bin", four), std::invalid_argument);
  {
    std::ofstream bad(dir / "bad.bin", std::ios::binary);
    bad << "aperture-horizons 2 5 3 8 4\n";
    bad.write(reinterpret_cast<const char*>(four.codes.data()), std::streamsize(four.codes.size()));
  }
  EXPECT_THROW(readHorizonMap(dir / "bad.bin"), std::runtime_error);
  std::ofstream(dir / "bits.bin") << "aperture-horizons 2 5 3 8 6\n";
  EXPECT_THROW(readHorizonMap(dir / "bits.bin"), std::runtime_error);

  std::filesystem::resize_file(dir / "h.bin", std::filesystem::file_size(dir / "h.bin") - 1);
  EXPECT_THROW(readHorizonMap(dir / "h.bin"), std::runtime_error);
  std::ofstream(dir / "other.bin") << "aperture-horizons 1 5 3 6\n";
  EXPECT_THROW(readHorizonMap(dir / "other.bin"), std::runtime_error);
  // A header asking for 16 TB is a damaged file, not an allocation.
  std::ofstream(dir / "huge.bin")
      << "aperture-horizons 4 1048576 1048576 16 8 r2-0 0123456789abcdef\n";
  EXPECT_THROW(readHorizonMap(dir / "huge.bin"), std::runtime_error);
  std::ofstream(dir / "text.bin") << "hello\n";
  EXPECT_THROW(readHorizonMap(dir / "text.bin"), std::runtime_error);
  EXPECT_THROW(readHorizonMap(dir / "missing.bin"), std::runtime_error);
  std::filesystem::remove_all(dir);
}

std::string fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Version 4 carries the checksum of its codes: a file whose header is
// intact but whose codes are not (a flipped byte, codes of the same range
// written over them, two rows swapped) is refused as an InputError naming
// it and saying to bake it again; the untouched file reads. Version 3 files
// (before the checksum of the codes) still read, their codes unchecked.
TEST(HorizonMap, CodesThatDoNotMatchTheirChecksumAreRefused) {
  test::TempDir dir;
  HorizonMap map;
  map.width = 6;
  map.height = 4;
  map.sourceChecksum = "r2-0123456789abcdef";
  for (int i = 0; i < map.width * map.height * kHorizonDirections; ++i) {
    map.codes.push_back(uint8_t(i * 13 % 256));
  }
  const std::filesystem::path good = dir.path() / "good.horizons";
  writeHorizonMap(good, map);
  EXPECT_EQ(readHorizonMap(good).codes, map.codes);
  const std::string bytes = fileBytes(good);
  const size_t codesStart = bytes.size() - map.codes.size();
  const auto damaged = [&](const std::string& name,
                           const std::function<void(std::string&)>& change) {
    std::string changed = bytes;
    change(changed);
    const std::filesystem::path path = dir.path() / name;
    std::ofstream(path, std::ios::binary) << changed;
    return path;
  };
  const std::filesystem::path cases[] = {
      damaged("flipped.horizons", [&](std::string& b) { b[codesStart + 77] ^= 0x01; }),
      damaged("random.horizons",
              [&](std::string& b) {
                for (size_t i = codesStart; i < b.size(); ++i) b[i] = char((i * 2654435761u) >> 7);
              }),
      damaged("swapped.horizons",
              [&](std::string& b) {
                const size_t row = size_t(map.width) * kHorizonDirections;
                std::swap_ranges(b.begin() + codesStart, b.begin() + codesStart + row,
                                 b.begin() + codesStart + row);
              }),
  };
  for (const std::filesystem::path& path : cases) {
    try {
      readHorizonMap(path);
      ADD_FAILURE() << path << " was read";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("do not match the checksum"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("bake it again"), std::string::npos) << e.what();
    }
  }
  // The same codes under a version 3 header: read, as before the checksum.
  const std::filesystem::path v3 = dir.path() / "v3.horizons";
  std::ofstream(v3, std::ios::binary) << "aperture-horizons 3 6 4 8 8 r2-0123456789abcdef\n"
                                      << bytes.substr(codesStart);
  EXPECT_EQ(readHorizonMap(v3).codes, map.codes);
  EXPECT_EQ(readHorizonMap(v3).sourceChecksum, map.sourceChecksum);
}

// A horizons file that is not a file (a FIFO: its open blocked for ever; a
// device; a folder) is refused for what it is, unopened. SIGALRM ends the
// test should a read block.
TEST(HorizonMap, FilesThatAreNotFilesAreRefusedUnopened) {
  test::TempDir dir;
  const std::filesystem::path fifo = dir.path() / "fifo.horizons";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  ::alarm(10);
  for (const auto& [path, says] :
       {std::pair{fifo.string(), " is a FIFO, not a file"},
        std::pair{std::string("/dev/zero"), " is a character device, not a file"},
        std::pair{dir.path().string(), " is a folder, not a file"}}) {
    try {
      readHorizonMap(path);
      ADD_FAILURE() << path << " was read";
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), "horizon map " + path + says);
    }
  }
  ::alarm(0);
}

// The sun's part above a straight horizon against counting points of its
// disk (planar at the sun's scale).
TEST(HorizonShading, SunFractionIsTheDiskAboveTheHorizon) {
  const float rs = 0.004653f;
  EXPECT_FLOAT_EQ(horizonSunFraction(0.1f, 0.1f, rs), 0.5f);
  EXPECT_FLOAT_EQ(horizonSunFraction(0.1f + rs, 0.1f, rs), 1.0f);
  EXPECT_FLOAT_EQ(horizonSunFraction(0.1f - rs, 0.1f, rs), 0.0f);
  EXPECT_EQ(horizonSunFraction(0.2f, 0.1f, 0.0f), 1.0f);
  EXPECT_EQ(horizonSunFraction(0.05f, 0.1f, 0.0f), 0.0f);
  for (float x = -1.2f; x <= 1.2f; x += 0.1f) {
    int above = 0, total = 0;
    for (int i = -200; i <= 200; ++i) {
      for (int j = -200; j <= 200; ++j) {
        const double u = i / 200.0, v = j / 200.0;
        if (u * u + v * v > 1) continue;
        ++total;
        if (v > -x) ++above;  // the disk's centre x radii above the horizon
      }
    }
    EXPECT_NEAR(horizonSunFraction(0.1f + x * rs, 0.1f, rs), double(above) / total, 3e-3) << x;
  }
}

// Horizon mode: the sun through the horizon, the sky from the aperture as in approx.
TEST(HorizonShading, SunFromTheHorizonSkyFromTheAperture) {
  ShadingInputs in;
  in.normal = glm::normalize(glm::vec3(0.2f, 0.1f, 1.0f));
  in.bentNormal = glm::normalize(glm::vec3(0.1f, 0.3f, 1.0f));
  in.apertureRad = 1.5f;
  const float elevation = 0.1f;
  in.sunDirection = {std::cos(elevation), 0.0f, std::sin(elevation)};
  in.sunIrradiance = glm::vec3(100.0f);
  in.skyRadiance = glm::vec3(5.0f);
  in.transfer = glm::vec3(0.8f);
  for (const float horizon : {-0.5f, elevation - 0.002f, elevation, elevation + 0.003f, 0.4f}) {
    in.sunHorizonRad = horizon;
    const ShadingTerms h = shadingTerms(in, ShadingMode::Horizon);
    const ShadingTerms a = shadingTerms(in, ShadingMode::Approx);
    const float f = horizonSunFraction(elevation, horizon, in.sunRadiusRad);
    EXPECT_FLOAT_EQ(h.sunFraction, f);
    const float nDotL = glm::dot(in.normal, in.sunDirection);
    EXPECT_NEAR(h.direct.r, in.albedo.r / float(kPi) * 100.0f * f * nDotL, 1e-5f);
    // The sky: Oat's cap as in approx, less the part of the sun the
    // horizon leaves in view (approx leaves out the part inside the cap).
    const float sunArea = float(capArea(in.sunRadiusRad));
    const float apertureArea = float(capArea(in.apertureRad));
    const float sky = 5.0f * float(kPi) * std::sin(1.5f) * std::sin(1.5f) *
                      glm::dot(in.normal, in.bentNormal) * (1.0f - f * sunArea / apertureArea);
    EXPECT_NEAR(h.skyIrradiance.g, sky, 1e-6f * sky) << horizon;
    EXPECT_NEAR(h.ambient.b, in.albedo.b / float(kPi) * sky * 0.8f, 1e-6f * sky) << horizon;
    // Which differs from approx's by the sun's share of the cap at most (1 %
    // for Oat's area of a sun wholly inside, a hair over the disk's).
    EXPECT_NEAR(h.skyIrradiance.r, a.skyIrradiance.r, 1.01f * sunArea / apertureArea * sky)
        << horizon;
  }
  // The aperture alone (approx) lights this sun, 0.1 rad high and 0.12 rad
  // inside the cap's rim: the horizon mode shadows it behind a ridge.
  in.sunHorizonRad = 0.2f;
  EXPECT_GT(shadingTerms(in, ShadingMode::Approx).sunFraction, 0.99f);
  EXPECT_EQ(shadingTerms(in, ShadingMode::Horizon).sunFraction, 0.0f);
}

}  // namespace
}  // namespace aal
