// Writers poll the interrupt flag (terrain/interrupt.h) between blocks of
// rows: a SIGTERM while an output is written leaves neither the output nor
// its temporary (aal-bake must not ignore it and exit 0).
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <vector>

#include "aperture/terrain/interrupt.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/tests/terrain/io/dem_test_util.h"

namespace aal {
namespace {

namespace fs = std::filesystem;

// Raises SIGTERM through the tools' handler for one test, then restores
// the default action and lowers the flag.
class InterruptedWrite : public ::testing::Test {
 protected:
  void SetUp() override {
    installInterruptHandler();
    std::raise(SIGTERM);
    ASSERT_TRUE(interruptFlag().load());
  }
  void TearDown() override {
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
    clearInterrupt();
  }
  test::TempDir dir_;
};

TEST_F(InterruptedWrite, ApertureMapIsNotLeftHalfWritten) {
  ApertureMap map;
  map.width = map.height = 64;
  map.texels.assign(map.texelCount() * 4, 0.5f);
  const fs::path path = dir_.path() / "a.exr";
  EXPECT_THROW(writeApertureMap(path.string(), map, true), Interrupted);
  EXPECT_TRUE(fs::is_empty(dir_.path()));
}

TEST_F(InterruptedWrite, GeoTiffIsNotLeftHalfWritten) {
  const std::vector<float> values(64 * 64, 1.0f);
  const fs::path path = dir_.path() / "svf.tif";
  EXPECT_THROW(writeFloatGeoTiff(path.string(), 64, 64, values.data(), GeoReference{}),
               Interrupted);
  EXPECT_TRUE(fs::is_empty(dir_.path()));
}

}  // namespace
}  // namespace aal
