// A HeightWindow holds only its rectangle of a DEM but reads it in the whole
// DEM's columns and rows; a HeightView of it, or of a whole Heightfield,
// reads the same heights the same way.
#include "aperture/terrain/height_window.h"

#include <gtest/gtest.h>

#include "aperture/terrain/height_view.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/texel_window.h"

namespace aal {
namespace {

// Height of DEM texel (x, y): tells every texel apart.
float heightOf(int x, int y) {
  return static_cast<float>(100 * x + y);
}

// A 10 x 8 DEM with every height.
Heightfield wholeDem() {
  Heightfield dem;
  dem.width = 10;
  dem.height = 8;
  dem.z.resize(dem.texelCount());
  for (int y = 0; y < dem.height; ++y) {
    for (int x = 0; x < dem.width; ++x) dem.z[dem.index(x, y)] = heightOf(x, y);
  }
  return dem;
}

// Columns 3..6 of rows 2..6 of `dem`, as a DEM read in parts holds them.
HeightWindow handMadeWindow(const Heightfield& dem, const TexelWindow& texels = {3, 2, 4, 5}) {
  HeightWindow window;
  window.dem = &dem;
  window.texels = texels;
  for (int y = texels.row; y < texels.row + texels.height; ++y) {
    for (int x = texels.col; x < texels.col + texels.width; ++x) {
      window.z.push_back(heightOf(x, y));
    }
  }
  return window;
}

TEST(HeightWindow, IndexesItsHeightsInTheWholeDemsColumnsAndRows) {
  const Heightfield dem = wholeDem();
  const HeightWindow window = handMadeWindow(dem);
  EXPECT_EQ(window.index(3, 2), 0u);
  EXPECT_EQ(window.index(6, 2), 3u);
  EXPECT_EQ(window.index(3, 3), 4u);
  EXPECT_EQ(window.index(6, 6), window.z.size() - 1);
  for (int y = 2; y <= 6; ++y) {
    for (int x = 3; x <= 6; ++x) EXPECT_EQ(window.at(x, y), heightOf(x, y)) << x << "," << y;
  }
}

TEST(HeightWindow, HoldsOnlyItsRectangle) {
  const Heightfield dem = wholeDem();
  const HeightWindow window = handMadeWindow(dem);
  EXPECT_FALSE(window.holdsColumn(2));
  EXPECT_TRUE(window.holdsColumn(3));
  EXPECT_TRUE(window.holdsColumn(6));
  EXPECT_FALSE(window.holdsColumn(7));
  EXPECT_FALSE(window.holdsRow(1));
  EXPECT_TRUE(window.holdsRow(2));
  EXPECT_TRUE(window.holdsRow(6));
  EXPECT_FALSE(window.holdsRow(7));
  EXPECT_TRUE(window.holds(3, 6));
  EXPECT_FALSE(window.holds(3, 7));
  EXPECT_FALSE(window.holds(7, 2));
  EXPECT_FALSE(window.holdsEveryTexel());
  // Every row but not every column, and the other way round, is a window.
  EXPECT_FALSE(handMadeWindow(dem, {0, 0, 9, 8}).holdsEveryTexel());
  EXPECT_FALSE(handMadeWindow(dem, {0, 1, 10, 7}).holdsEveryTexel());
  EXPECT_TRUE(handMadeWindow(dem, {0, 0, 10, 8}).holdsEveryTexel());
}

TEST(HeightWindow, FlagsVoidsInTheWholeDemsColumnsAndRows) {
  const Heightfield dem = wholeDem();
  HeightWindow window = handMadeWindow(dem);
  EXPECT_FALSE(window.isVoid(4, 5));  // no mask: no voids
  window.voidMask.assign(window.z.size(), 0);
  window.voidMask[window.index(4, 5)] = 1;
  for (int y = 2; y <= 6; ++y) {
    for (int x = 3; x <= 6; ++x) EXPECT_EQ(window.isVoid(x, y), x == 4 && y == 5) << x << "," << y;
  }
}

TEST(HeightView, OfAWindowReadsTheWindowsHeightsAndVoids) {
  const Heightfield dem = wholeDem();
  HeightWindow window = handMadeWindow(dem);
  window.voidMask.assign(window.z.size(), 0);
  window.voidMask[window.index(6, 2)] = 1;
  const HeightView view = window;
  EXPECT_EQ(view.dem, &dem);
  EXPECT_EQ(view.z.data(), window.z.data());
  for (int y = 0; y < dem.height; ++y) {
    for (int x = 0; x < dem.width; ++x) {
      ASSERT_EQ(view.holds(x, y), window.holds(x, y)) << x << "," << y;
      if (!view.holds(x, y)) continue;
      EXPECT_EQ(view.at(x, y), heightOf(x, y)) << x << "," << y;
      EXPECT_EQ(view.isVoid(x, y), x == 6 && y == 2) << x << "," << y;
    }
  }
}

TEST(HeightView, OfAHeightfieldHoldsEveryTexelOfTheDem) {
  Heightfield dem = wholeDem();
  dem.voidMask.assign(dem.texelCount(), 0);
  dem.voidMask[dem.index(9, 7)] = 1;
  const HeightView view = dem;
  EXPECT_EQ(view.dem, &dem);
  EXPECT_TRUE(view.texels.covers(dem));
  for (int y = 0; y < dem.height; ++y) {
    for (int x = 0; x < dem.width; ++x) {
      ASSERT_TRUE(view.holds(x, y));
      EXPECT_EQ(view.at(x, y), dem.at(x, y));
      EXPECT_EQ(view.isVoid(x, y), dem.isVoid(x, y));
    }
  }
  EXPECT_TRUE(view.isVoid(9, 7));
  EXPECT_FALSE(view.holds(10, 0));
  EXPECT_FALSE(view.holds(0, -1));
}

TEST(TexelWindow, ContainsARectangleWhoseCornersItHolds) {
  const TexelWindow window{3, 2, 4, 5};
  EXPECT_TRUE(window.contains(window));
  EXPECT_TRUE(window.contains(TexelWindow{4, 3, 2, 2}));
  EXPECT_FALSE(window.contains(TexelWindow{2, 3, 2, 2}));
  EXPECT_FALSE(window.contains(TexelWindow{5, 3, 3, 2}));
  EXPECT_FALSE(window.contains(TexelWindow{4, 1, 2, 2}));
  EXPECT_FALSE(window.contains(TexelWindow{4, 6, 2, 2}));
}

TEST(HeightWindow, CopiedOutOfAWholeDemHoldsWhatADemReadInPartsWould) {
  Heightfield dem = wholeDem();
  dem.voidMask.assign(dem.texelCount(), 0);
  dem.voidMask[dem.index(4, 3)] = 1;  // inside the window
  dem.voidMask[dem.index(0, 0)] = 1;  // outside it
  const TexelWindow texels{3, 2, 4, 5};
  const HeightWindow copied = windowOf(dem, texels);
  const HeightWindow expected = handMadeWindow(dem, texels);
  EXPECT_EQ(copied.dem, &dem);
  EXPECT_EQ(copied.z, expected.z);
  ASSERT_EQ(copied.voidMask.size(), copied.z.size());
  for (int y = 2; y <= 6; ++y) {
    for (int x = 3; x <= 6; ++x) EXPECT_EQ(copied.isVoid(x, y), x == 4 && y == 3) << x << "," << y;
  }
  dem.voidMask.clear();
  EXPECT_TRUE(windowOf(dem, texels).voidMask.empty());
}

}  // namespace
}  // namespace aal
