// Quadtree level of detail for the terrain (CDLOD: Strugar 2009,
// "Continuous Distance-Dependent Level of Detail for Rendering Heightmaps",
// JGT 14(4); docs/rendering.md). The DEM is covered by a quadtree whose leaves
// (level 0) span kLodPatchQuads DEM cells; a node of level l spans
// kLodPatchQuads * 2^l cells and is drawn as one patch (terrain/view/lod_patch.h)
// with quads 2^l cells wide. Every frame the CPU selects nodes by their
// distance to the camera — level l within range_l of it — and culls the ones
// outside the view frustum; the vertex shader morphs each patch onto the
// coarser grid over the last kLodMorphFraction of its range, so levels switch
// without popping and neighbouring levels meet without cracks or T-junctions.
//
// The ranges come from the geometric error of each level: every
// node knows how far its drawn surface may lie from the DEM's (a bound, in
// metres, of the height difference), and a level is drawn only where its
// largest error projects to at most LodSettings::maxErrorPixels on screen. The
// per-pixel normals, apertures and albedo come from textures, so a coarse
// mesh over smooth or distant terrain loses little of the picture.
//
// Crack-free by construction: a node of level l touches only areas of level l
// or l + 1, and where it touches level l + 1 its vertices are fully morphed
// while the coarser ones are not morphing yet, when every node of level l is
// no wider (3D box diagonal D_l) than (1 - kLodMorphFraction) of the distance
// between range_l and range_(l+1) (Strugar §3.2). makeLodRanges keeps every
// pair of ranges at least that far apart.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/view/lod_patch.h"

namespace aal {

// Fraction of each level's range (range_l - range_(l-1)) over which it
// morphs into the next level (Strugar's morph start ratio 0.7 for 0.3).
constexpr double kLodMorphFraction = 0.3;

// Per-frame choices that are the user's (FrameSettings::lod).
struct LodSettings {
  // The largest geometric error of the drawn surface, in pixels on screen
  // (a height error e metres at distance d covers e f / d pixels, f the focal
  // length in pixels): a level is drawn only where its nodes' largest error
  // covers at most this many. 0: automatic, lodAutomaticErrorPixels of the
  // viewport. The bound is a worst case (the largest height difference over
  // the level).
  double maxErrorPixels = 0;
  // Debugging only: false draws the selected levels without morphing, which
  // opens cracks between levels on rough terrain (the crack test checks that
  // it does).
  bool morph = true;
  // Tests only: false draws back faces even where the camera cannot see them
  // (LodSelection::backFacesHidden stays false), to show that culling them
  // leaves the picture as it is.
  bool cullBackFaces = true;
};

// World-space axis-aligned box of a node (metres, the frame of docs/design.md §1).
struct LodBox {
  glm::dvec3 min{0.0}, max{0.0};
};

// The quadtree of one DEM: per node the height range of its texels (its
// edges included, so a vertex's height always lies in its node's box) and
// its geometric error. Memory: 12 bytes per node, about 0.012 bytes per DEM
// texel.
class LodQuadtree {
 public:
  // Throws std::invalid_argument for DEMs under 2 x 2 texels. The errors are
  // those of the surface the vertex shader draws from the prefiltered heights
  // (terrain/view/height_mips.h): a bound on the height difference between a
  // node's unmorphed patch and the DEM's triangulated surface.
  explicit LodQuadtree(const Heightfield& field);
  // The same for a DEM known only by its size, cell size and the height
  // range (min, max) of each leaf's texels: leafHeights(i, j) for leaf
  // column i, row j (texels [i, i + 1] * kLodPatchQuads, clamped). Without
  // the heights, a node's error is taken as its height range.
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
  // Bound on how far (m, vertically) node (i, j)'s drawn patch lies from the
  // DEM's surface; 0 at level 0, which draws the DEM's own texels.
  float nodeErrorM(int level, int i, int j) const;
  // The largest of nodeErrorM over the nodes of `level`.
  double maxErrorM(int level) const { return maxErrorM_[static_cast<size_t>(level)]; }

  int demWidth() const { return width_; }
  int demHeight() const { return height_; }
  glm::dvec2 cellSizeM() const { return {cellXM_, cellYM_}; }
  size_t memoryBytes() const;

 private:
  int width_ = 0, height_ = 0;
  double cellXM_ = 1, cellYM_ = 1;
  std::vector<std::vector<glm::vec2>> heights_;  // [level][j * nodesAcross + i]: min, max
  std::vector<std::vector<float>> errors_;       // [level][j * nodesAcross + i]
  std::vector<double> maxDiagonalM_, maxErrorM_;
  void buildInnerNodes();
  void measureErrors(const Heightfield& field);
  void summarise();
};

// Selection distances per level for an error scale P (pixels per metre of
// height error per metre of distance: the focal length in pixels over the
// pixels of error allowed). Level l + 1 takes over, morphing, where its
// largest error e_(l+1) covers at most one allowed error: the morph of level
// l towards it starts no closer than P e_(l+1). Every range is at least the
// one before plus D_(l-1) / (1 - kLodMorphFraction) (crack-free; see the
// top), the finest at least one cell; P = 0 gives the closest ranges that
// allows, the coarsest selection.
struct LodRanges {
  double errorScale = 0;          // P
  std::vector<double> rangeM;     // range_l; the root's is unbounded
  std::vector<glm::vec2> morphM;  // morph start and end per level (kLodNoMorph: none)
};
LodRanges makeLodRanges(const LodQuadtree& tree, double errorScale, bool morph = true);

// The automatic error allowed in a viewport `viewportHeightPx` high: 4 pixels
// at 720 lines, in proportion to the height (so that the picture's error is
// the same fraction of it at any size), at least one. At 1280x720 it kept the
// tone-mapped picture within 0.8 % RMSE of the finest mesh's in every view
// measured (docs/performance.md) with 1.3-9x fewer triangles; 4 pixels at
// 640x360 did not (1.1-1.4 %).
double lodAutomaticErrorPixels(double viewportHeightPx);
// The error scale P at which `maxErrorPixels` of error are allowed in a
// viewport `viewportHeightPx` high with vertical field of view
// `verticalFovDeg`.
double lodViewErrorScale(double viewportHeightPx, double verticalFovDeg, double maxErrorPixels);
// The largest P at which a camera anywhere over the DEM, near the ground and
// looking in every direction (no frustum culling), selects at most
// `triangleBudget` triangles; +infinity when any P fits. Cameras sampled on a
// 5 x 5 grid; bisection on P. 0 when even the coarsest selection exceeds the
// budget.
double lodBudgetErrorScale(const LodQuadtree& tree, size_t triangleBudget);

// The patches to draw: whole nodes first, then the nodes drawn by quadrant,
// quadrant 0 (north-west) to 3 (south-east).
struct LodSelection {
  std::vector<LodPatch> patches;
  uint32_t wholeCount = 0;
  std::array<uint32_t, 4> quadrantCount{};
  size_t triangles = 0;                   // as drawn (degenerate ones past the DEM edge included)
  std::vector<uint32_t> patchesPerLevel;  // whole nodes and quadrants, per level
  double errorScale = 0;                  // the P it was selected with
  // The camera sees no back face of the drawn mesh (lodHidesBackFaces): the
  // renderer may cull them.
  bool backFacesHidden = false;
};

// True when no back face of the drawn mesh can be seen from `cameraM`: the
// camera is over the DEM (within its rectangle) and above its highest
// texel. A heightfield is a sheet z = h(x, y); a ray from such a camera that
// reaches a back face has crossed the sheet downwards first, so a front
// face hides it. Every drawn height (prefiltered means, their morph) lies
// within the texels' range, so this holds for the mesh too. From beside or
// below the sheet (a view under its open edge) back faces can show.
bool lodHidesBackFaces(const LodQuadtree& tree, glm::dvec3 cameraM);

// Strugar's LODSelect (§3.1): nodes within their level's range, refined where
// the next finer range reaches them; nodes whose box is outside the frustum
// of `viewProj` (Vulkan clip space) are dropped, unless it is null.
LodSelection selectLod(const LodQuadtree& tree, const LodRanges& ranges, glm::dvec3 cameraM,
                       const glm::mat4* viewProj);

// The triangles a frame draws unless asked otherwise (the triangle budget
// of aal-render's and aal-view's --triangles and of the Python render).
constexpr size_t kDefaultTriangleBudget = 2'000'000;

// The frame's selection: P = min(budget scale, view scale); should the
// selection still exceed `triangleBudget` (a camera the budget's samples
// missed), P shrinks for this frame until it fits or reaches 0.
struct LodFrame {
  glm::dvec3 cameraM{0.0};
  glm::mat4 viewProj{1.0f};
  double viewportHeightPx = 720, verticalFovDeg = 45;
  size_t triangleBudget = 0;
  double budgetErrorScale = 0;  // lodBudgetErrorScale of the tree and budget
  LodSettings settings;
};
LodSelection selectLodForFrame(const LodQuadtree& tree, const LodFrame& frame);

}  // namespace aal
