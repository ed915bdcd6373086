// The bake cache (preprocess/aperture_cache.h): an entry is used only when
// every pixel verifies; a damaged one is rebaked and replaced with one
// warning line (a truncated entry must not make every later render of its
// DEM exit 2 until it is deleted by hand).
#include "aperture/preprocess/aperture_cache.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "aperture/tests/preprocess/bake_test_util.h"
#include "aperture/tests/preprocess/map_test_util.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

namespace fs = std::filesystem;

// Points the cache at a fresh folder for one test.
class ApertureCache : public testing::Test {
 protected:
  void SetUp() override {
    if (const char* old = std::getenv("AAL_CACHE_DIR")) saved_ = old;
    ::setenv("AAL_CACHE_DIR", (dir_.path() / "cache").c_str(), 1);
  }
  void TearDown() override {
    if (saved_.empty()) {
      ::unsetenv("AAL_CACHE_DIR");
    } else {
      ::setenv("AAL_CACHE_DIR", saved_.c_str(), 1);
    }
  }

  // The cache's answer for field_, with what it said on stderr.
  CachedAperture lookUp(std::string* said = nullptr) {
    testing::internal::CaptureStderr();
    CachedAperture cached = cachedOrBakedAperture(field_, "wavy.tif", options_, /*quiet=*/true);
    const std::string err = testing::internal::GetCapturedStderr();
    if (said) *said = err;
    return cached;
  }

  // The cache entry, baked and written by a first look-up.
  fs::path bakedEntry() {
    const CachedAperture first = lookUp();
    EXPECT_FALSE(first.path.empty());
    return first.path;
  }

  // Expects a look-up to rebake the damaged entry at `path`: one warning line
  // naming it and `why`, and an entry equal to a fresh bake.
  void expectRebaked(const fs::path& path, const std::string& why) {
    std::string said;
    const CachedAperture again = lookUp(&said);
    ASSERT_EQ(again.path, path);
    EXPECT_EQ(said.rfind("warning: ", 0), 0u) << said;
    EXPECT_EQ(std::count(said.begin(), said.end(), '\n'), 1) << said;
    EXPECT_NE(said.find(path.string()), std::string::npos) << said;
    EXPECT_NE(said.find(why), std::string::npos) << said;
    EXPECT_EQ(readApertureMap(path.string()).texels, fresh_.texels);
    // The replaced entry verifies: the next look-up says nothing.
    std::string next;
    EXPECT_EQ(lookUp(&next).path, path);
    EXPECT_EQ(next, "");
  }

  test::TempDir dir_;
  std::string saved_;
  const BakeOptions options_ = [] {
    BakeOptions o;
    o.azimuths = 16;
    return o;
  }();
  const Heightfield field_ = test::makeField(
      48, 40, 30.0, [](double x, double y) { return 150 * std::sin(x / 200) * std::cos(y / 150); });
  // What a fresh bake's entry holds.
  const ApertureMap fresh_ = [this] {
    ApertureMap map = bakeApertures(field_, options_).aperture;
    const std::string path = (dir_.path() / "fresh.exr").string();
    writeApertureMap(path, map, /*halfFloat=*/true);
    return readApertureMap(path);
  }();
};

TEST_F(ApertureCache, AVerifiedEntryIsUsedAsIs) {
  const fs::path path = bakedEntry();
  const auto written = fs::last_write_time(path);
  std::string said;
  EXPECT_EQ(lookUp(&said).path, path);
  EXPECT_EQ(said, "");
  EXPECT_EQ(fs::last_write_time(path), written);
  EXPECT_EQ(findCachedAperture(field_, "wavy.tif", options_), path);
}

TEST_F(ApertureCache, ATruncatedEntryIsRebakedAndReplaced) {
  const fs::path path = bakedEntry();
  fs::resize_file(path, fs::file_size(path) * 2 / 3);
  std::string why;
  EXPECT_TRUE(findCachedAperture(field_, "wavy.tif", options_, &why).empty());
  EXPECT_NE(why.find("truncated or corrupt"), std::string::npos) << why;
  expectRebaked(path, "truncated or corrupt");
}

TEST_F(ApertureCache, AnEntryWithAFlippedPixelByteIsRebaked) {
  const fs::path path = bakedEntry();
  // A byte of the last rows' RLE data: the pixels change (or no longer decode).
  test::flipByteFromEnd(path.string(), 7);
  expectRebaked(path, path.string());
  for (const std::streamoff fromEnd : {1, 40, 300}) {
    test::flipByteFromEnd(path.string(), fromEnd);
    expectRebaked(path, path.string());
  }
}

TEST_F(ApertureCache, AnEntryWithoutAPixelChecksumIsRebaked) {
  const fs::path path = bakedEntry();
  test::removePixelChecksum(path.string());
  // Readable, but not verified.
  EXPECT_NO_THROW(readApertureMap(path.string()));
  expectRebaked(path, "no pixel checksum");
}

// An entry that is a FIFO (or any file that is not a regular one) is not
// opened, which would block for ever, but reported as what it is and
// replaced by a fresh bake; a FIFO where the horizons beside it go is no
// horizons, and replaced too. SIGALRM ends the test should a read block.
TEST_F(ApertureCache, AnEntryThatIsAFifoIsRebakedWithoutOpeningIt) {
  const fs::path path = bakedEntry();
  fs::remove(path);
  ASSERT_EQ(::mkfifo(path.c_str(), 0644), 0);
  ::alarm(10);
  std::string why;
  EXPECT_TRUE(findCachedAperture(field_, "wavy.tif", options_, &why).empty());
  EXPECT_NE(why.find(path.string() + " is a FIFO, not a file"), std::string::npos) << why;
  expectRebaked(path, "is a FIFO, not a file");
  EXPECT_TRUE(fs::is_regular_file(path));

  BakeOptions withHorizons = options_;
  withHorizons.horizons = true;
  const fs::path beside = cachedHorizonsPath(field_, withHorizons);
  ASSERT_EQ(::mkfifo(beside.c_str(), 0644), 0);
  EXPECT_EQ(findCachedHorizons(field_, withHorizons).width, 0);
  ::alarm(0);
}

// A cache entry that is one of the run's inputs (AAL_CACHE_DIR pointed at
// the inputs' folder, and a file there with the entry's name) is never
// written over: the bake stays in memory, with a warning naming both.
TEST_F(ApertureCache, AnEntryThatIsAnInputOfTheRunIsNotWrittenOver) {
  const fs::path path = cachedAperturePath(field_, options_);
  fs::create_directories(path.parent_path());
  const std::string precious = "not an aperture map: the user's file";
  for (const bool asDem : {false, true}) {
    std::ofstream(path, std::ios::binary) << precious;
    testing::internal::CaptureStderr();
    const CachedAperture cached =
        asDem ? cachedOrBakedAperture(field_, path.string(), options_, true)
              : cachedOrBakedAperture(field_, "wavy.tif", options_, true, {"", path.string()});
    const std::string said = testing::internal::GetCapturedStderr();
    EXPECT_TRUE(cached.path.empty()) << asDem;
    EXPECT_EQ(cached.map.width, field_.width) << asDem;
    std::ifstream in(path, std::ios::binary);
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), precious) << asDem;
    EXPECT_NE(said.find("warning: not caching the aperture map: its cache entry " + path.string() +
                        " is the input " + path.string()),
              std::string::npos)
        << said;
  }
}

// A cache filled before the checksum changed names its entries by the older checksum
// (and they carry it): such an entry of this DEM is still used; one of
// another DEM is not.
TEST_F(ApertureCache, AnEntryNamedByTheOlderChecksumIsUsed) {
  const fs::path entry = bakedEntry();
  const std::string name = entry.filename().string();
  ASSERT_EQ(name.rfind(heightfieldChecksum(field_) + "-s", 0), 0u) << name;
  const std::string options = name.substr(name.find("-s"));
  ApertureMap map = readApertureMap(entry.string());
  map.info.sourceChecksum = legacyHeightfieldChecksum(field_);
  const fs::path legacy = entry.parent_path() / (map.info.sourceChecksum + options);
  writeApertureMap(legacy.string(), map, /*halfFloat=*/true);
  fs::remove(entry);
  std::string said;
  EXPECT_EQ(lookUp(&said).path, legacy);
  EXPECT_EQ(said, "");
  EXPECT_FALSE(fs::exists(entry));

  // The same name with another DEM's older checksum is not this DEM's.
  fs::remove(legacy);
  map.info.sourceChecksum = "0123456789abcdef";
  writeApertureMap((entry.parent_path() / (map.info.sourceChecksum + options)).string(), map, true);
  EXPECT_TRUE(findCachedAperture(field_, "wavy.tif", options_).empty());
}

// With options.horizons (aal-view's background bake): the bake's
// directional horizons come back with the map and are cached beside it, so
// a cache hit has them too; an entry without them (aal-render's), or with
// a damaged horizons file, is a hit without horizons, not an error.
TEST_F(ApertureCache, KeepsTheBakesHorizonsBesideTheEntry) {
  BakeOptions withHorizons = options_;
  withHorizons.horizons = true;
  const HorizonMap expected = bakeApertures(field_, withHorizons).horizons;
  ASSERT_EQ(expected.width, field_.width);
  const CachedAperture baked = cachedOrBakedAperture(field_, "wavy.tif", withHorizons, true);
  ASSERT_FALSE(baked.path.empty());
  EXPECT_EQ(baked.horizons.codes, expected.codes);
  const fs::path beside = cachedHorizonsPath(field_, withHorizons);
  EXPECT_EQ(beside.parent_path(), baked.path.parent_path());
  EXPECT_EQ(readHorizonMap(beside).codes, expected.codes);
  const CachedAperture hit = cachedOrBakedAperture(field_, "wavy.tif", withHorizons, true);
  EXPECT_EQ(hit.path, baked.path);
  EXPECT_EQ(hit.horizons.codes, expected.codes);
  EXPECT_EQ(hit.horizons.directions, withHorizons.horizonDirections);
  // The same entry asked for without horizons: none read.
  EXPECT_EQ(lookUp().horizons.width, 0);
  // Damaged or missing: the map is still a hit.
  fs::resize_file(beside, fs::file_size(beside) / 2);
  const CachedAperture damaged = cachedOrBakedAperture(field_, "wavy.tif", withHorizons, true);
  EXPECT_EQ(damaged.path, baked.path);
  EXPECT_EQ(damaged.horizons.width, 0);
  fs::remove(beside);
  EXPECT_EQ(findCachedHorizons(field_, withHorizons).width, 0);
  // Other directions or bits are another file.
  BakeOptions sixteen = withHorizons;
  sixteen.horizonDirections = 16;
  sixteen.horizonBits = 4;
  EXPECT_NE(cachedHorizonsPath(field_, sixteen), beside);
}

}  // namespace
}  // namespace aal
