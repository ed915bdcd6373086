// Quadtree level of detail for the terrain (CDLOD: Strugar 2009,
// "Continuous Distance-Dependent Level of Detail for Rendering Heightmaps",
// JGT 14(4); DESIGN §8). The DEM is covered by a quadtree whose leaves
// (level 0) span kLodPatchQuads DEM cells; a node of level l spans
// kLodPatchQuads * 2^l cells and is drawn as one patch (terrain/lod_patch.h)
// with quads 2^l cells wide. Every frame the CPU selects nodes by their
// distance to the camera — level l within range_l = K 2^l, so a quad covers
// about the same number of pixels at every level — and culls the ones outside
// the view frustum; the vertex shader morphs each patch onto the coarser grid
// over the last kLodMorphFraction of its range, so levels switch without
// popping and neighbouring levels meet without cracks or T-junctions.
//
// Crack-free by construction: a node of level l touches only areas of level l
// or l + 1, and where it touches level l + 1 its vertices are fully morphed
// while the coarser ones are not morphing yet, when every node of level l is
// no wider (3D box diagonal D_l) than (1 - kLodMorphFraction) of the distance
// between range_l and range_(l+1) (Strugar §3.2). lodMinimumRangeScale gives
// the smallest K with that property; every range scale used is at least it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "heightfield.h"
#include "lod_patch.h"

namespace aal {

// Fraction of each level's range (range_l - range_(l-1)) over which it
// morphs into the next level (Strugar's morph start ratio 0.7 for 0.3).
constexpr double kLodMorphFraction = 0.3;

// Per-frame choices that are the user's (FrameSettings::lod).
struct LodSettings {
  // The viewport's part of the ranges: the largest quad drawn covers about
  // this many pixels (a level's quads cover between half this and this).
  double maxQuadPixels = 1.0;
  // Debugging only: false draws the selected levels without morphing, which
  // opens cracks between levels on rough terrain (the crack test checks that
  // it does).
  bool morph = true;
};

// World-space axis-aligned box of a node (metres, DESIGN §1 frame).
struct LodBox {
  glm::dvec3 min{0.0}, max{0.0};
};

// The quadtree of one DEM: per node the height range of its texels (its
// edges included, so a vertex's height always lies in its node's box).
// Memory: 8 bytes per node, about 0.01 bytes per DEM texel.
class LodQuadtree {
 public:
  // Throws std::invalid_argument for DEMs under 2 x 2 texels.
  explicit LodQuadtree(const Heightfield& field);
  // The same for a DEM known only by its size, cell size and the height
  // range (min, max) of each leaf's texels: leafHeights(i, j) for leaf
  // column i, row j (texels [i, i + 1] * kLodPatchQuads, clamped).
  LodQuadtree(int width, int height, glm::dvec2 cellSizeM,
              const std::function<glm::vec2(int, int)>& leafHeights);

  // Level levels() - 1 is the root, a single node.
  int levels() const { return static_cast<int>(heights_.size()); }
  int nodesAcross(int level) const;
  int nodesDown(int level) const;
  // Node (i, j) of `level` covers texel columns [i, i + 1] * nodeTexels(level)
  // and rows likewise (clamped to the DEM).
  int nodeTexels(int level) const { return kLodPatchQuads << level; }
  glm::vec2 nodeHeights(int level, int i, int j) const;
  LodBox nodeBox(int level, int i, int j) const;
  // Largest 3D box diagonal of the nodes of `level` (m).
  double maxNodeDiagonalM(int level) const { return maxDiagonalM_[static_cast<size_t>(level)]; }

  int demWidth() const { return width_; }
  int demHeight() const { return height_; }
  glm::dvec2 cellSizeM() const { return {cellXM_, cellYM_}; }
  size_t memoryBytes() const;

 private:
  int width_ = 0, height_ = 0;
  double cellXM_ = 1, cellYM_ = 1;
  std::vector<std::vector<glm::vec2>> heights_;  // [level][j * nodesAcross + i]: min, max
  std::vector<double> maxDiagonalM_;
  void buildInnerNodes();
};

// Selection distances per level for range scale K (range_l = K 2^l).
struct LodRanges {
  double scaleM = 0;              // K
  std::vector<double> rangeM;     // range_l; the root's is unbounded
  std::vector<glm::vec2> morphM;  // morph start and end per level (kLodNoMorph: none)
};
LodRanges makeLodRanges(const LodQuadtree& tree, double scaleM, bool morph = true);

// The smallest K that keeps the selection crack-free (see the top).
double lodMinimumRangeScale(const LodQuadtree& tree);
// The K at which the largest quad covers `maxQuadPixels` pixels in a viewport
// `viewportHeightPx` high with vertical field of view `verticalFovDeg`.
double lodPixelRangeScale(const LodQuadtree& tree, double viewportHeightPx, double verticalFovDeg,
                          double maxQuadPixels);
// The largest K at which a camera anywhere over the DEM, near the ground and
// looking in every direction (no frustum culling), selects at most
// `triangleBudget` triangles; +infinity when the whole DEM at full resolution
// fits. Cameras sampled on a 5 x 5 grid; bisection on K. At least
// lodMinimumRangeScale, even when that exceeds the budget.
double lodBudgetRangeScale(const LodQuadtree& tree, size_t triangleBudget);

// The patches to draw: whole nodes first, then the nodes drawn by quadrant,
// quadrant 0 (north-west) to 3 (south-east).
struct LodSelection {
  std::vector<LodPatch> patches;
  uint32_t wholeCount = 0;
  std::array<uint32_t, 4> quadrantCount{};
  size_t triangles = 0;                   // as drawn (degenerate ones past the DEM edge included)
  std::vector<uint32_t> patchesPerLevel;  // whole nodes and quadrants, per level
  double scaleM = 0;                      // the K it was selected with
};

// Strugar's LODSelect (§3.1): nodes within their level's range, refined where
// the next finer range reaches them; nodes whose box is outside the frustum
// of `viewProj` (Vulkan clip space) are dropped, unless it is null.
LodSelection selectLod(const LodQuadtree& tree, const LodRanges& ranges, glm::dvec3 cameraM,
                       const glm::mat4* viewProj);

// The frame's selection: K = min(budget scale, pixel scale), at least the
// crack-free minimum; should the selection still exceed `triangleBudget`
// (a camera the budget's samples missed), K shrinks for this frame until it
// fits or reaches the minimum.
struct LodFrame {
  glm::dvec3 cameraM{0.0};
  glm::mat4 viewProj{1.0f};
  double viewportHeightPx = 720, verticalFovDeg = 45;
  size_t triangleBudget = 0;
  double budgetScaleM = 0;  // lodBudgetRangeScale of the tree and budget
  LodSettings settings;
};
LodSelection selectLodForFrame(const LodQuadtree& tree, const LodFrame& frame);

}  // namespace aal
