// The geometric error of the quadtree LOD (terrain/view/quadtree_lod.h) and the
// prefiltered heights it is measured on (terrain/view/height_mips.h), against
// brute force: block means of the DEM, and every DEM texel held against the
// triangles a node's patch draws.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "aperture/terrain/synthetic.h"
#include "aperture/terrain/view/height_mips.h"
#include "aperture/terrain/view/quadtree_lod.h"

namespace aal {
namespace {

// Rough fBm, not a power of two across (so nodes and mip texels reach past
// the edges), 20 m cells.
const Heightfield& roughDem() {
  static const Heightfield f = [] {
    SyntheticTerrainOptions o;
    o.width = 301;
    o.height = 213;
    o.cellSizeM = 20;
    o.amplitudeM = 400;
    o.featureSizeTexels = 40;
    return makeSyntheticTerrain(o);
  }();
  return f;
}

// Mean of level `level`'s texel (k, m): its 2^l x 2^l DEM texels, the edge
// repeated beyond the DEM.
double blockMean(const Heightfield& f, int level, int k, int m) {
  const int n = 1 << level;
  double sum = 0;
  for (int y = m * n; y < (m + 1) * n; ++y) {
    for (int x = k * n; x < (k + 1) * n; ++x) {
      sum += f.at(std::clamp(x, 0, f.width - 1), std::clamp(y, 0, f.height - 1));
    }
  }
  return sum / (n * n);
}

TEST(HeightMips, LevelTexelsAreBlockMeansWithTheEdgeRepeated) {
  const Heightfield& f = roughDem();
  const HeightMips mips(f, 6);
  ASSERT_EQ(mips.levels(), 6);
  double worst = 0;
  for (int level = 0; level < 6; ++level) {
    const int n = 1 << level;
    // Texel centres of the level, from one before the DEM to one past it.
    for (int m = -1; m <= (f.height + n - 1) / n; ++m) {
      for (int k = -1; k <= (f.width + n - 1) / n; ++k) {
        const double column = (k + 0.5) * n - 0.5, row = (m + 0.5) * n - 0.5;
        // Level 0 is the DEM's own bilinear surface, clamped.
        const double expected =
            level == 0 ? f.bilinearHeight(column, row) : blockMean(f, level, k, m);
        worst = std::max(worst, std::abs(mips.at(level, column, row) - expected));
      }
    }
  }
  EXPECT_LT(worst, 1e-3);  // float sums of up to 1024 heights of ~400 m
}

// The upper pair and the lower pair summed apart, then together: the order
// the renderer's uploads sum in too.
TEST(HeightMips, MeanOf2x2SumsThePairsOfRowsFirst) {
  EXPECT_EQ(meanOf2x2(1, 2, 3, 4), 2.5f);
  // 1e8 + 1 rounds to 1e8: only the pairs' order gives 0 (one after another
  // gives 0.25, columns first 0.5).
  EXPECT_EQ(meanOf2x2(1e8f, 1, -1e8f, 1), 0.0f);
}

// A level texel holds exactly meanOf2x2 of the four texels of the level
// above (the DEM's edge repeated), and a fetch at its centre returns it.
TEST(HeightMips, LevelTexelsAreMeanOf2x2OfTheLevelAbove) {
  const Heightfield& f = roughDem();
  const HeightMips mips(f, 3);
  // Texel (k, m) of a level, read at its centre.
  const auto texel = [&](int level, int k, int m) -> float {
    if (level == 0) return f.at(std::clamp(k, 0, f.width - 1), std::clamp(m, 0, f.height - 1));
    const int n = 1 << level;
    return mips.at(level, (k + 0.5) * n - 0.5, (m + 0.5) * n - 0.5);
  };
  for (int level = 1; level <= 2; ++level) {
    const int n = 1 << level;
    for (int m = -1; m <= (f.height + n - 1) / n; ++m) {
      for (int k = -1; k <= (f.width + n - 1) / n; ++k) {
        const int l = level - 1;
        ASSERT_EQ(texel(level, k, m),
                  meanOf2x2(texel(l, 2 * k, 2 * m), texel(l, 2 * k + 1, 2 * m),
                            texel(l, 2 * k, 2 * m + 1), texel(l, 2 * k + 1, 2 * m + 1)))
            << "level " << level << ", texel " << k << ", " << m;
      }
    }
  }
}

TEST(HeightMips, FetchesAreBilinearBetweenTexelCentres) {
  const Heightfield& f = roughDem();
  const HeightMips mips(f, 6);
  const int level = 3, n = 8;
  for (int m = 0; m < 20; ++m) {
    for (int k = 0; k < 30; ++k) {
      const double c0 = (k + 0.5) * n - 0.5, r0 = (m + 0.5) * n - 0.5;
      const double fx = 0.3, fy = 0.8;
      const double top = blockMean(f, level, k, m) * (1 - fx) + blockMean(f, level, k + 1, m) * fx;
      const double bottom =
          blockMean(f, level, k, m + 1) * (1 - fx) + blockMean(f, level, k + 1, m + 1) * fx;
      EXPECT_NEAR(mips.at(level, c0 + fx * n, r0 + fy * n), top * (1 - fy) + bottom * fy, 1e-3);
    }
  }
}

// The height of node (i, j)'s unmorphed patch at DEM texel (column, row):
// the triangle (diagonal north-west to south-east) of level l's vertex
// heights, as terrain.vert draws it.
double patchHeight(const HeightMips& mips, const Heightfield& f, int level, int column, int row) {
  const double step = 1 << level;
  const double a = std::floor(column / step), b = std::floor(row / step);
  const double fx = column / step - a, fy = row / step - b;
  const auto vertex = [&](double va, double vb) {
    return mips.at(level, std::min(va * step, double(f.width - 1)),
                   std::min(vb * step, double(f.height - 1)));
  };
  const double nw = vertex(a, b), ne = vertex(a + 1, b), sw = vertex(a, b + 1),
               se = vertex(a + 1, b + 1);
  return fx >= fy ? nw + (ne - nw) * fx + (se - ne) * fy : nw + (sw - nw) * fy + (se - sw) * fx;
}

TEST(LodError, NodeErrorsBoundTheDrawnSurfacesDistanceFromTheDem) {
  const Heightfield& f = roughDem();
  const LodQuadtree tree(f);
  const HeightMips mips(f, 6);
  ASSERT_GE(tree.levels(), 4);
  for (int level = 0; level < tree.levels(); ++level) {
    const int size = tree.nodeTexels(level);
    double worstActual = 0;
    for (int j = 0; j < tree.nodesDown(level); ++j) {
      for (int i = 0; i < tree.nodesAcross(level); ++i) {
        double actual = 0;
        for (int row = j * size; row <= std::min((j + 1) * size, f.height - 1); ++row) {
          for (int column = i * size; column <= std::min((i + 1) * size, f.width - 1); ++column) {
            actual = std::max(
                actual, std::abs(patchHeight(mips, f, level, column, row) - f.at(column, row)));
          }
        }
        EXPECT_LE(actual, tree.nodeErrorM(level, i, j) + 1e-3) << level << ": " << i << ", " << j;
        worstActual = std::max(worstActual, actual);
      }
    }
    if (level == 0) {
      EXPECT_EQ(tree.maxErrorM(0), 0.0);
    } else {
      // A bound, but not a loose one: the LOD would draw too much.
      EXPECT_GT(worstActual, 0.5 * tree.maxErrorM(level)) << level;
      EXPECT_GT(tree.maxErrorM(level), tree.maxErrorM(level - 1)) << level;
    }
    std::printf("level %d: largest error %.2f m, bound %.2f m\n", level, worstActual,
                tree.maxErrorM(level));
  }
}

TEST(LodError, DrawnLevelsStayWithinTheErrorOnScreen) {
  const Heightfield& f = roughDem();
  const LodQuadtree tree(f);
  for (double pixels : {1.0, 4.0, 16.0}) {
    const double scale = lodViewErrorScale(720, 40, pixels);
    const LodRanges ranges = makeLodRanges(tree, scale);
    // Level l - 1 starts morphing into level l only where level l's error
    // covers at most `pixels`.
    for (int level = 1; level + 1 < tree.levels(); ++level) {
      EXPECT_GE(ranges.morphM[size_t(level - 1)].x * (1 + 1e-6), scale * tree.maxErrorM(level))
          << pixels << " px, level " << level;
    }
    for (glm::dvec3 camera :
         {glm::dvec3(0, 0, 900), glm::dvec3(-2500, 1800, 700), glm::dvec3(9000, -6000, 3000)}) {
      const LodSelection s = selectLod(tree, ranges, camera, nullptr);
      ASSERT_FALSE(s.patches.empty());
      for (size_t p = 0; p < s.patches.size(); ++p) {
        const LodPatch& patch = s.patches[p];
        const int level = int(patch.node.w);
        const int size = tree.nodeTexels(level);
        const int i = int(patch.node.x) / size, j = int(patch.node.y) / size;
        // A quadrant is drawn where its child was out of range: as far.
        const bool whole = p < s.wholeCount;
        LodBox box = tree.nodeBox(level, i, j);
        if (!whole && level > 0) {
          size_t q = 0, first = s.wholeCount;
          while (p >= first + s.quadrantCount[q]) first += s.quadrantCount[q++];
          const int ci = 2 * i + int(q % 2), cj = 2 * j + int(q / 2);
          if (ci >= tree.nodesAcross(level - 1) || cj >= tree.nodesDown(level - 1)) continue;
          box = tree.nodeBox(level - 1, ci, cj);
        }
        const double distance = glm::length(glm::clamp(camera, box.min, box.max) - camera);
        // Its unmorphed error covers at most `pixels` there.
        EXPECT_GE(distance * (1 + 1e-9), scale * tree.maxErrorM(level))
            << pixels << " px, level " << level;
      }
    }
  }
}

}  // namespace
}  // namespace aal
