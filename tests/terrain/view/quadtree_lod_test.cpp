// The quadtree LOD on the CPU (terrain/view/quadtree_lod.h, terrain/view/lod_patch.h):
// the patch mesh, the morph, the selection's coverage, budget and culling,
// and that the morphed patches meet without cracks and move without popping
// (the vertex shader's computation emulated with the C++ twins).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <optional>
#include <set>
#include <utility>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "aperture/terrain/synthetic.h"
#include "aperture/terrain/view/camera.h"
#include "aperture/terrain/view/lod_patch.h"
#include "aperture/terrain/view/quadtree_lod.h"

namespace aal {
namespace {

constexpr int kQuads = kLodPatchQuads;
// One pixel of error at 1280 x 720 with a 40 degree field of view.
const double kViewScale = lodViewErrorScale(720, 40, 1);

// Rough fBm: 1025 x 1025 texels, 10 m cells, about 300 m of relief.
const Heightfield& roughDem() {
  static const Heightfield f = [] {
    SyntheticTerrainOptions o;
    o.width = o.height = 1025;
    o.cellSizeM = 10;
    o.amplitudeM = 300;
    o.featureSizeTexels = 64;
    return makeSyntheticTerrain(o);
  }();
  return f;
}

// Bilinear height at a continuous texel position, as the linear sampler of
// terrain.vert reads it (clamped to the edge).
float heightAt(const Heightfield& f, glm::vec2 texel) {
  const float x = std::clamp(texel.x, 0.0f, float(f.width - 1));
  const float y = std::clamp(texel.y, 0.0f, float(f.height - 1));
  const int x0 = std::min(int(x), f.width - 2), y0 = std::min(int(y), f.height - 2);
  const float fx = x - float(x0), fy = y - float(y0);
  const float top = f.at(x0, y0) * (1 - fx) + f.at(x0 + 1, y0) * fx;
  const float bottom = f.at(x0, y0 + 1) * (1 - fx) + f.at(x0 + 1, y0 + 1) * fx;
  return top * (1 - fy) + bottom * fy;
}

glm::vec3 worldAt(const Heightfield& f, glm::vec2 texel) {
  const glm::vec2 half = 0.5f * glm::vec2(f.width - 1, f.height - 1);
  return {(texel.x - half.x) * float(f.cellSizeXM), (half.y - texel.y) * float(f.cellSizeYM),
          heightAt(f, texel)};
}

// terrain.vert on the CPU: the morphed world position of a patch grid point.
glm::vec3 vertexPosition(const Heightfield& f, const LodPatch& p, glm::vec2 gridPoint,
                         glm::vec3 camera) {
  const glm::vec2 dem(f.width, f.height);
  const float distance = glm::length(worldAt(f, lodPatchTexel(p, gridPoint, dem)) - camera);
  const float k = lodMorphFactor(distance, glm::vec2(p.morph));
  return worldAt(f, lodPatchTexel(p, lodMorphGridPoint(gridPoint, k), dem));
}

// A drawn piece: a whole patch or one quadrant of it, as grid points
// [g0, g0 + n] in x and y.
struct Piece {
  LodPatch patch;
  glm::ivec2 g0{0};
  int n = kQuads;
  // Footprint in texels (unclamped): [lo, hi].
  glm::vec2 lo() const { return glm::vec2(patch.node) + glm::vec2(g0) * patch.node.z; }
  glm::vec2 hi() const { return lo() + float(n) * patch.node.z; }
  int level() const { return int(patch.node.w); }
};

std::vector<Piece> pieces(const LodSelection& s) {
  std::vector<Piece> out;
  size_t index = 0;
  for (; index < s.wholeCount; ++index) out.push_back({s.patches[index], {0, 0}, kQuads});
  for (int q = 0; q < 4; ++q) {
    for (uint32_t i = 0; i < s.quadrantCount[size_t(q)]; ++i, ++index) {
      out.push_back({s.patches[index], {(q % 2) * kQuads / 2, (q / 2) * kQuads / 2}, kQuads / 2});
    }
  }
  return out;
}

struct View {
  Camera camera;
  glm::mat4 viewProj{1.0f};
};

View viewFrom(const LodQuadtree& tree, glm::dvec3 position, glm::dvec3 lookAt) {
  View v;
  v.camera.position = position;
  v.camera.lookAt = lookAt;
  v.camera.verticalFovDeg = 40;
  const LodBox root = tree.nodeBox(tree.levels() - 1, 0, 0);
  const glm::dvec2 extent(root.max.x - root.min.x, root.max.y - root.min.y);
  const DepthRange range = depthRangeFor(v.camera, extent, root.min.z, root.max.z);
  v.viewProj = projectionMatrix(v.camera, 16.0 / 9.0, range) * viewMatrix(v.camera);
  return v;
}

// Cameras low over the rough DEM looking in several directions.
std::vector<glm::dvec3> lowCameras(const Heightfield& f) {
  std::vector<glm::dvec3> cameras;
  for (auto [x, y] :
       {std::pair{0.0, 0.0}, {-2500.0, 1800.0}, {3100.0, -3900.0}, {-4900.0, -4900.0}}) {
    const glm::vec2 texel(x / f.cellSizeXM + 0.5 * (f.width - 1),
                          0.5 * (f.height - 1) - y / f.cellSizeYM);
    cameras.emplace_back(x, y, heightAt(f, texel) + 40.0);
  }
  return cameras;
}

TEST(LodPatch, IndicesCoverEveryQuadOnceQuadrantByQuadrant) {
  const std::vector<uint32_t> indices = makeLodPatchIndices();
  ASSERT_EQ(indices.size(), size_t(kLodPatchIndices));
  std::set<std::pair<uint32_t, uint32_t>> quads;
  constexpr uint32_t stride = kQuads + 1;
  for (size_t t = 0; t < indices.size(); t += 6) {
    // Each quad's first vertex is its north-west corner.
    const uint32_t nw = indices[t];
    const uint32_t col = nw % stride, row = nw / stride;
    const uint32_t quadrant = uint32_t(t / kLodQuadrantIndices);
    EXPECT_EQ((row >= kQuads / 2) * 2 + (col >= kQuads / 2), quadrant) << col << "," << row;
    EXPECT_TRUE(quads.insert({col, row}).second);
    // North-west to south-east diagonal, counter-clockwise seen from above.
    const uint32_t expected[6] = {nw, nw + stride, nw + stride + 1, nw, nw + stride + 1, nw + 1};
    for (int i = 0; i < 6; ++i) EXPECT_EQ(indices[t + size_t(i)], expected[i]);
  }
  EXPECT_EQ(quads.size(), size_t(kQuads) * kQuads);
}

TEST(LodPatch, FullMorphPutsEveryVertexOnTheCoarserGrid) {
  for (int y = 0; y <= kQuads; ++y) {
    for (int x = 0; x <= kQuads; ++x) {
      const glm::vec2 g(x, y);
      EXPECT_EQ(lodMorphGridPoint(g, 0.0f), g);
      const glm::vec2 full = lodMorphGridPoint(g, 1.0f);
      // On the coarser grid, and on the coarser point at or below it.
      EXPECT_EQ(full, glm::vec2(x - x % 2, y - y % 2));
      const glm::vec2 half = lodMorphGridPoint(g, 0.5f);
      EXPECT_EQ(half, glm::vec2(x - 0.5f * float(x % 2), y - 0.5f * float(y % 2)));
    }
  }
}

TEST(LodPatch, MorphFactorRampsFromZeroToOneOverTheRange) {
  const glm::vec2 range(700.0f, 1000.0f);
  EXPECT_EQ(lodMorphFactor(0.0f, range), 0.0f);
  EXPECT_EQ(lodMorphFactor(700.0f, range), 0.0f);
  EXPECT_FLOAT_EQ(lodMorphFactor(850.0f, range), 0.5f);
  EXPECT_EQ(lodMorphFactor(1000.0f, range), 1.0f);
  EXPECT_EQ(lodMorphFactor(5000.0f, range), 1.0f);
  EXPECT_EQ(lodMorphFactor(1e9f, {kLodNoMorph, 2 * kLodNoMorph}), 0.0f);
}

TEST(QuadtreeLod, NodeHeightsBoundTheirTexels) {
  const Heightfield& f = roughDem();
  const LodQuadtree tree(f);
  EXPECT_EQ(tree.levels(), 6);  // 1024 cells = 32 leaves of 32 cells
  for (int level = 0; level < tree.levels(); ++level) {
    for (auto [i, j] : {std::pair{0, 0}, {1, 0}, {0, 1}}) {
      if (i >= tree.nodesAcross(level) || j >= tree.nodesDown(level)) continue;
      const int size = tree.nodeTexels(level);
      float lo = 1e30f, hi = -1e30f;
      for (int r = j * size; r <= std::min((j + 1) * size, f.height - 1); ++r) {
        for (int c = i * size; c <= std::min((i + 1) * size, f.width - 1); ++c) {
          lo = std::min(lo, f.at(c, r));
          hi = std::max(hi, f.at(c, r));
        }
      }
      EXPECT_EQ(tree.nodeHeights(level, i, j), glm::vec2(lo, hi)) << level << " " << i << " " << j;
    }
  }
  EXPECT_LT(double(tree.memoryBytes()) / double(f.texelCount()), 0.02);
}

TEST(QuadtreeLod, SelectionCoversTheDemOnceWithoutCulling) {
  const Heightfield& f = roughDem();
  const LodQuadtree tree(f);
  int mostLevels = 0;
  // From the coarsest ranges to one pixel of error (level 0 everywhere on
  // this small rough DEM).
  for (double scale : {0.0, kViewScale / 16, kViewScale}) {
    for (const glm::dvec3& camera : lowCameras(f)) {
      const LodSelection s = selectLod(tree, makeLodRanges(tree, scale), camera, nullptr);
      // Coverage at the finest piece size (a quadrant of a leaf, 16 texels).
      const int cell = kQuads / 2, n = (f.width - 1) / cell;
      std::vector<int> covered(size_t(n) * n, 0);
      for (const Piece& p : pieces(s)) {
        const glm::ivec2 lo(p.lo() / float(cell)), hi(p.hi() / float(cell));
        for (int y = lo.y; y < std::min(hi.y, n); ++y) {
          for (int x = lo.x; x < std::min(hi.x, n); ++x) ++covered[size_t(y) * n + x];
        }
      }
      EXPECT_EQ(std::count(covered.begin(), covered.end(), 1), ptrdiff_t(covered.size()));
      int levelsUsed = 0;
      for (uint32_t c : s.patchesPerLevel) levelsUsed += c > 0;
      mostLevels = std::max(mostLevels, levelsUsed);
    }
  }
  EXPECT_GE(mostLevels, 4);
}

// Distance (m) from `camera` to the box of the node a patch draws.
double patchDistance(const LodQuadtree& tree, const LodPatch& p, glm::dvec3 camera) {
  const int level = int(p.node.w), size = tree.nodeTexels(level);
  const LodBox box = tree.nodeBox(level, int(p.node.x) / size, int(p.node.y) / size);
  return glm::length(glm::clamp(camera, box.min, box.max) - camera);
}

TEST(QuadtreeLod, EachDrawListsItsPatchesNearestFirst) {
  // Nearer terrain drawn first hides what lies behind it from the depth test
  // before that is shaded; each of the frame's draws (whole nodes, each
  // quadrant) keeps its instances in order.
  const Heightfield& f = roughDem();
  const LodQuadtree tree(f);
  int checked = 0;
  for (const glm::dvec3& camera : lowCameras(f)) {
    const LodSelection s = selectLod(tree, makeLodRanges(tree, kViewScale / 16), camera, nullptr);
    size_t first = 0;
    std::array<uint32_t, 5> counts{s.wholeCount, s.quadrantCount[0], s.quadrantCount[1],
                                   s.quadrantCount[2], s.quadrantCount[3]};
    for (uint32_t count : counts) {
      for (size_t i = first + 1; i < first + count; ++i) {
        EXPECT_LE(patchDistance(tree, s.patches[i - 1], camera),
                  patchDistance(tree, s.patches[i], camera));
        ++checked;
      }
      first += count;
    }
    EXPECT_EQ(first, s.patches.size());
  }
  EXPECT_GT(checked, 50);
}

TEST(QuadtreeLod, BackFacesAreHiddenOnlyFromAboveTheWholeDem) {
  const Heightfield& f = roughDem();
  const LodQuadtree tree(f);
  const float top = *std::max_element(f.z.begin(), f.z.end());
  const glm::dvec2 half = 0.5 * demExtentM(f);
  // Over the DEM and above its highest texel: hidden.
  EXPECT_TRUE(lodHidesBackFaces(tree, {0, 0, top + 1.0}));
  EXPECT_TRUE(lodHidesBackFaces(tree, {0.99 * half.x, -0.99 * half.y, top + 1.0}));
  // Below the highest texel (a valley's floor may be far below), beside the
  // DEM (its open edge seen from below its rim), or under it: not.
  EXPECT_FALSE(lodHidesBackFaces(tree, {0, 0, top - 1.0}));
  EXPECT_FALSE(lodHidesBackFaces(tree, {1.01 * half.x, 0, top + 1000.0}));
  EXPECT_FALSE(lodHidesBackFaces(tree, {0, -1.01 * half.y, top + 1000.0}));
  const LodSelection s =
      selectLod(tree, makeLodRanges(tree, kViewScale), {0, 0, top + 1.0}, nullptr);
  EXPECT_TRUE(s.backFacesHidden);
}

// For every pair of drawn pieces that share an edge: their levels differ by
// at most one, and their morphed vertices on the edge are the same points
// (so the mesh has neither cracks nor T-junctions). Returns the largest gap
// (m) between a vertex on one side and the nearest vertex on the other.
double worstSeamGap(const Heightfield& f, const LodSelection& s, glm::vec3 camera, int* levelJump,
                    int* seams) {
  const std::vector<Piece> all = pieces(s);
  double worst = 0;
  // Morphed points of piece p on its edge `axis` = `at`, within [from, to] along the other axis.
  const auto edgePoints = [&](const Piece& p, int axis, float at, float from, float to) {
    std::vector<glm::vec3> points;
    for (int i = 0; i <= p.n; ++i) {
      glm::ivec2 g = p.g0;
      g[axis] += (at == p.lo()[axis]) ? 0 : p.n;
      g[1 - axis] += i;
      const float along = p.patch.node[1 - axis] + float(g[1 - axis]) * p.patch.node.z;
      if (along < from || along > to) continue;
      points.push_back(vertexPosition(f, p.patch, glm::vec2(g), camera));
    }
    return points;
  };
  const auto gap = [](const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
    double most = 0;
    for (const glm::vec3& p : a) {
      double nearest = 1e30;
      for (const glm::vec3& q : b) nearest = std::min(nearest, double(glm::length(p - q)));
      most = std::max(most, nearest);
    }
    return most;
  };
  for (size_t i = 0; i < all.size(); ++i) {
    for (size_t j = 0; j < all.size(); ++j) {
      const Piece &a = all[i], &b = all[j];
      for (int axis = 0; axis < 2; ++axis) {
        if (a.hi()[axis] != b.lo()[axis]) continue;
        const float from = std::max(a.lo()[1 - axis], b.lo()[1 - axis]);
        const float to = std::min(a.hi()[1 - axis], b.hi()[1 - axis]);
        if (to <= from) continue;
        ++*seams;
        *levelJump = std::max(*levelJump, std::abs(a.level() - b.level()));
        const auto pa = edgePoints(a, axis, a.hi()[axis], from, to);
        const auto pb = edgePoints(b, axis, b.lo()[axis], from, to);
        worst = std::max({worst, gap(pa, pb), gap(pb, pa)});
      }
    }
  }
  return worst;
}

TEST(QuadtreeLod, MorphedPatchesMeetAcrossLevelsWithoutCracks) {
  const Heightfield& f = roughDem();
  const LodQuadtree tree(f);
  // The coarsest ranges (tight against the crack-free bound), several
  // levels on screen, one pixel of error.
  for (double scale : {0.0, kViewScale / 16, kViewScale}) {
    int seams = 0;
    for (const glm::dvec3& camera : lowCameras(f)) {
      const LodSelection s = selectLod(tree, makeLodRanges(tree, scale), camera, nullptr);
      int jump = 0;
      const double gap = worstSeamGap(f, s, glm::vec3(camera), &jump, &seams);
      EXPECT_LE(jump, 1);
      // The same points up to float rounding of positions ~5 km out.
      EXPECT_LT(gap, 2e-3) << "camera " << camera.x << ", " << camera.y << ", scale " << scale;
    }
    EXPECT_GT(seams, 100) << "scale " << scale;
  }
}

TEST(QuadtreeLod, WithoutMorphingTheLevelsLeaveCracks) {
  // The seam check above can fail: unmorphed, the finer side's odd vertices
  // keep their own heights off the coarser side's straight edges.
  const Heightfield& f = roughDem();
  const LodQuadtree tree(f);
  const glm::dvec3 camera = lowCameras(f)[0];
  const LodSelection s = selectLod(tree, makeLodRanges(tree, 0, false), camera, nullptr);
  int jump = 0, seams = 0;
  EXPECT_GT(worstSeamGap(f, s, glm::vec3(camera), &jump, &seams), 0.5);
}

// Height of the drawn (morphed) surface at world point xy: the triangle of
// the piece that covers it.
std::optional<float> surfaceHeight(const Heightfield& f, const std::vector<Piece>& all,
                                   glm::vec2 xy, glm::vec3 camera) {
  const glm::vec2 half = 0.5f * glm::vec2(f.width - 1, f.height - 1);
  const glm::vec2 texel(xy.x / float(f.cellSizeXM) + half.x, half.y - xy.y / float(f.cellSizeYM));
  for (const Piece& p : all) {
    if (texel.x < p.lo().x || texel.y < p.lo().y || texel.x > p.hi().x || texel.y > p.hi().y)
      continue;
    // Morphing moves vertices by at most one quad: search the quads around.
    const glm::ivec2 c = glm::ivec2((texel - glm::vec2(p.patch.node)) / p.patch.node.z);
    for (int y = std::max(c.y - 1, p.g0.y); y <= std::min(c.y + 1, p.g0.y + p.n - 1); ++y) {
      for (int x = std::max(c.x - 1, p.g0.x); x <= std::min(c.x + 1, p.g0.x + p.n - 1); ++x) {
        const glm::vec3 nw = vertexPosition(f, p.patch, {x, y}, camera);
        const glm::vec3 sw = vertexPosition(f, p.patch, {x, y + 1}, camera);
        const glm::vec3 se = vertexPosition(f, p.patch, {x + 1, y + 1}, camera);
        const glm::vec3 ne = vertexPosition(f, p.patch, {x + 1, y}, camera);
        for (const auto& t : {std::array{nw, sw, se}, std::array{nw, se, ne}}) {
          const glm::vec2 a(t[0]), b(t[1]), d(t[2]);
          const float area = (b.x - a.x) * (d.y - a.y) - (d.x - a.x) * (b.y - a.y);
          if (std::abs(area) < 1e-6f) continue;
          const float u = ((b.x - xy.x) * (d.y - xy.y) - (d.x - xy.x) * (b.y - xy.y)) / area;
          const float v = ((d.x - xy.x) * (a.y - xy.y) - (a.x - xy.x) * (d.y - xy.y)) / area;
          const float w = 1 - u - v;
          if (u >= -1e-5f && v >= -1e-5f && w >= -1e-5f)
            return u * t[0].z + v * t[1].z + w * t[2].z;
        }
      }
    }
  }
  return std::nullopt;
}

// Largest change of the drawn surface's height at fixed points between two
// camera positions 2 m apart, flying over the rough DEM through several
// level switches.
double largestStepChange(bool morph) {
  const Heightfield& f = roughDem();
  const LodQuadtree tree(f);
  const LodRanges ranges = makeLodRanges(tree, 0, morph);
  std::vector<glm::vec2> points;
  for (int i = 0; i < 400; ++i)
    points.emplace_back(-1500.0f + 7.3f * float(i), 900.0f - 3.1f * float(i));
  std::vector<float> previous;
  double worst = 0;
  for (int step = 0; step <= 600; ++step) {
    const glm::vec3 camera(-2000.0f + 2.0f * float(step), -1000.0f, 400.0f);
    const std::vector<Piece> all = pieces(selectLod(tree, ranges, camera, nullptr));
    std::vector<float> heights;
    for (const glm::vec2& p : points)
      heights.push_back(surfaceHeight(f, all, p, camera).value_or(NAN));
    if (!previous.empty()) {
      for (size_t i = 0; i < heights.size(); ++i) {
        EXPECT_FALSE(std::isnan(heights[i])) << "a hole at point " << i;
        worst = std::max(worst, double(std::abs(heights[i] - previous[i])));
      }
    }
    previous = heights;
  }
  return worst;
}

TEST(QuadtreeLod, MorphingKeepsTheSurfaceContinuousAsTheCameraMoves) {
  const double morphing = largestStepChange(true), popping = largestStepChange(false);
  std::printf("largest height change per 2 m of flight: %.3f m morphing, %.3f m without\n",
              morphing, popping);
  EXPECT_LT(morphing, 0.1 * popping);
  EXPECT_LT(morphing, 1.0);
}

// A DEM of any size without its heights: smooth hills of ~600 m (as leaf
// height ranges), 30 m cells.
LodQuadtree syntheticTree(int size) {
  return LodQuadtree(size, size, {30.0, 30.0}, [](int i, int j) {
    const float base = 300.0f + 300.0f * std::sin(0.05f * float(i)) * std::cos(0.07f * float(j));
    return glm::vec2(base - 15.0f, base + 15.0f);
  });
}

TEST(QuadtreeLod, TrianglesStayWithinTheBudgetWhateverTheDemSize) {
  for (size_t budget : {size_t(500'000), size_t(2'000'000)}) {
    for (int size : {1024, 8192, 32768}) {
      const LodQuadtree tree = syntheticTree(size);
      LodFrame frame;
      frame.triangleBudget = budget;
      frame.budgetErrorScale = lodBudgetErrorScale(tree, budget);
      frame.viewportHeightPx = 720;
      frame.verticalFovDeg = 40;
      size_t most = 0;
      // The same cameras (world positions, DEM centred) for every size.
      for (const glm::dvec3& position : {glm::dvec3(0, 0, 900), glm::dvec3(-5000, 3000, 700)}) {
        for (double azimuth = 0; azimuth < 6.28; azimuth += 0.785) {
          const glm::dvec3 look =
              position + glm::dvec3(std::sin(azimuth), std::cos(azimuth), -0.15);
          const View v = viewFrom(tree, position, look);
          frame.cameraM = position;
          frame.viewProj = v.viewProj;
          const LodSelection s = selectLodForFrame(tree, frame);
          EXPECT_LE(s.triangles, budget) << size;
          most = std::max(most, s.triangles);
        }
      }
      std::printf("%5d^2, budget %7zu: levels %2d, P %.3g, at most %7zu triangles in view\n", size,
                  budget, tree.levels(), frame.budgetErrorScale, most);
      // The budget is spent, not wasted: with culling a view draws a good
      // part of it (the budget holds for a camera looking every way).
      EXPECT_GT(most, budget / 10) << size;
    }
  }
}

TEST(QuadtreeLod, FrustumCullingDropsNodesBehindTheCamera) {
  const LodQuadtree tree = syntheticTree(8192);
  const glm::dvec3 position(0, 0, 900);
  const View v = viewFrom(tree, position, position + glm::dvec3(0, 1, -0.15));  // looking north
  const LodRanges ranges = makeLodRanges(tree, kViewScale);
  const LodSelection culled = selectLod(tree, ranges, position, &v.viewProj);
  const LodSelection all = selectLod(tree, ranges, position, nullptr);
  EXPECT_LT(culled.triangles, all.triangles / 2);
  int behind = 0;
  for (const Piece& p : pieces(culled)) {
    // World y of the piece's northern edge (texel rows grow southwards).
    const double northY = (0.5 * (tree.demHeight() - 1) - p.lo().y) * 30.0;
    if (northY < position.y - 1.0) ++behind;
  }
  EXPECT_EQ(behind, 0);
}

}  // namespace
}  // namespace aal
