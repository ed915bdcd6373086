#include "aperture/terrain/view/quadtree_lod.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <tbb/parallel_for.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "aperture/shaders/config.h"
#include "aperture/terrain/units.h"
#include "aperture/terrain/view/height_mips.h"

namespace aal {

namespace {

// A finite stand-in for an unbounded range: single precision holds it and
// its doublings up to level 31 (the shader computes in floats).
constexpr double kUnboundedRangeM = 1e12;

int ceilDiv(int a, int b) {
  return (a + b - 1) / b;
}

size_t patchTriangles(bool whole) {
  const size_t quads = size_t(kLodPatchQuads) * kLodPatchQuads;
  return whole ? 2 * quads : quads / 2;
}

// The six planes of Vulkan's clip volume (-w <= x, y <= w, 0 <= z <= w) as
// world-space plane equations a x + b y + c z + d >= 0 (Gribb and Hartmann
// 2001, "Fast Extraction of Viewing Frustum Planes from the World-View-
// Projection Matrix").
std::array<glm::dvec4, 6> frustumPlanes(const glm::mat4& m) {
  const auto row = [&](int i) { return glm::dvec4(m[0][i], m[1][i], m[2][i], m[3][i]); };
  const glm::dvec4 x = row(0), y = row(1), z = row(2), w = row(3);
  return {w + x, w - x, w + y, w - y, z, w - z};
}

bool outsideFrustum(const LodBox& box, const std::array<glm::dvec4, 6>& planes) {
  for (const glm::dvec4& p : planes) {
    // The box corner farthest along the plane's normal.
    const glm::dvec3 corner(p.x >= 0 ? box.max.x : box.min.x, p.y >= 0 ? box.max.y : box.min.y,
                            p.z >= 0 ? box.max.z : box.min.z);
    if (p.x * corner.x + p.y * corner.y + p.z * corner.z + p.w < 0) return true;
  }
  return false;
}

bool intersectsSphere(const LodBox& box, glm::dvec3 centre, double radius) {
  const glm::dvec3 nearest = glm::clamp(centre, box.min, box.max);
  const glm::dvec3 d = nearest - centre;
  return glm::dot(d, d) <= radius * radius;
}

class Selector {
 public:
  // Stops adding patches once more than `limit` triangles are selected.
  Selector(const LodQuadtree& tree, const LodRanges& ranges, glm::dvec3 camera,
           const glm::mat4* viewProj, size_t limit = std::numeric_limits<size_t>::max())
      : tree_(tree), ranges_(ranges), camera_(camera), cull_(viewProj != nullptr), limit_(limit) {
    if (viewProj) planes_ = frustumPlanes(*viewProj);
    whole_.reserve(256);
    for (auto& q : quadrants_) q.reserve(256);
  }

  LodSelection run() {
    const int root = tree_.levels() - 1;
    select(root, 0, 0);
    nearestFirst(whole_);
    for (auto& q : quadrants_) nearestFirst(q);
    LodSelection s;
    s.errorScale = ranges_.errorScale;
    s.patchesPerLevel.assign(static_cast<size_t>(tree_.levels()), 0);
    s.wholeCount = static_cast<uint32_t>(whole_.size());
    s.patches.reserve(whole_.size() + quadrants_[0].size() + quadrants_[1].size() +
                      quadrants_[2].size() + quadrants_[3].size());
    for (const Placed& p : whole_) s.patches.push_back(p.patch);
    s.triangles = whole_.size() * patchTriangles(true);
    for (size_t q = 0; q < 4; ++q) {
      s.quadrantCount[q] = static_cast<uint32_t>(quadrants_[q].size());
      for (const Placed& p : quadrants_[q]) s.patches.push_back(p.patch);
      s.triangles += quadrants_[q].size() * patchTriangles(false);
    }
    for (const LodPatch& p : s.patches) ++s.patchesPerLevel[static_cast<size_t>(p.node.w)];
    return s;
  }

 private:
  LodPatch patch(int level, int i, int j) const {
    const float size = static_cast<float>(tree_.nodeTexels(level));
    return {glm::vec4(i * size, j * size, float(1 << level), float(level)),
            glm::vec4(ranges_.morphM[static_cast<size_t>(level)], 0.0f, 0.0f)};
  }

  // Strugar 2009, §3.1, LODSelect: true when the node's area is taken care
  // of (drawn, culled, or off the DEM), false when it is beyond its level's
  // range and its parent must draw it.
  bool select(int level, int i, int j) {
    if (triangles_ > limit_) return true;
    if (i >= tree_.nodesAcross(level) || j >= tree_.nodesDown(level)) return true;
    const LodBox box = tree_.nodeBox(level, i, j);
    const bool root = level == tree_.levels() - 1;
    if (!root && !intersectsSphere(box, camera_, ranges_.rangeM[size_t(level)])) return false;
    if (cull_ && outsideFrustum(box, planes_)) return true;
    if (level == 0 || !intersectsSphere(box, camera_, ranges_.rangeM[size_t(level - 1)])) {
      whole_.push_back({distanceTo(box), patch(level, i, j)});
      triangles_ += patchTriangles(true);
      return true;
    }
    for (int q = 0; q < 4; ++q) {
      const int ci = 2 * i + q % 2, cj = 2 * j + q / 2;
      if (!select(level - 1, ci, cj)) {
        quadrants_[size_t(q)].push_back({distanceTo(box), patch(level, i, j)});
        triangles_ += patchTriangles(false);
      }
    }
    return true;
  }

  // A patch and its box's distance from the camera.
  struct Placed {
    double distanceM;
    LodPatch patch;
  };

  double distanceTo(const LodBox& box) const {
    return glm::length(glm::clamp(camera_, box.min, box.max) - camera_);
  }

  // Nearest first, so that the depth test rejects what nearer terrain hides
  // before it is shaded: a rasterizer draws a draw's instances in order, and
  // a fragment's cost is its texture fetches (docs/rendering.md, "Drawing
  // order"). Stable: equal distances keep the traversal's order, so a
  // selection is drawn the same way every time.
  static void nearestFirst(std::vector<Placed>& patches) {
    std::stable_sort(patches.begin(), patches.end(),
                     [](const Placed& a, const Placed& b) { return a.distanceM < b.distanceM; });
  }

  const LodQuadtree& tree_;
  const LodRanges& ranges_;
  glm::dvec3 camera_;
  bool cull_;
  size_t limit_, triangles_ = 0;
  std::array<glm::dvec4, 6> planes_{};
  std::vector<Placed> whole_;
  std::array<std::vector<Placed>, 4> quadrants_;
};

}  // namespace

LodQuadtree::LodQuadtree(const Heightfield& field)
    : LodQuadtree(
          field.width, field.height, {field.cellSizeXM, field.cellSizeYM}, [&](int i, int j) {
            // Every texel of the leaf, its east and south edges included.
            const int c0 = i * kLodPatchQuads, c1 = std::min(c0 + kLodPatchQuads, field.width - 1);
            const int r0 = j * kLodPatchQuads, r1 = std::min(r0 + kLodPatchQuads, field.height - 1);
            float lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();
            for (int r = r0; r <= r1; ++r) {
              const float* row = field.z.data() + field.index(0, r);
              const auto [mn, mx] = std::minmax_element(row + c0, row + c1 + 1);
              lo = std::min(lo, *mn);
              hi = std::max(hi, *mx);
            }
            return glm::vec2(lo, hi);
          }) {
  measureErrors(field);
  summarise();
}

LodQuadtree::LodQuadtree(int width, int height, glm::dvec2 cellSizeM,
                         const std::function<glm::vec2(int, int)>& leafHeights)
    : width_(width), height_(height), cellXM_(cellSizeM.x), cellYM_(cellSizeM.y) {
  if (width_ < 2 || height_ < 2) throw std::invalid_argument("a DEM needs at least 2x2 texels");
  const int leavesX = nodesAcross(0), leavesY = nodesDown(0);
  int levels = 1;
  while ((1 << (levels - 1)) < std::max(leavesX, leavesY)) ++levels;
  heights_.resize(static_cast<size_t>(levels));
  heights_[0].resize(size_t(leavesX) * leavesY);
  tbb::parallel_for(0, leavesY, [&](int j) {
    for (int i = 0; i < leavesX; ++i) heights_[0][size_t(j) * leavesX + i] = leafHeights(i, j);
  });
  buildInnerNodes();
  // Without the heights: the surface lies within the node's height range.
  errors_.resize(heights_.size());
  for (size_t level = 0; level < heights_.size(); ++level) {
    for (const glm::vec2& h : heights_[level]) errors_[level].push_back(level == 0 ? 0 : h.y - h.x);
  }
  summarise();
}

void LodQuadtree::buildInnerNodes() {
  const int levels = this->levels();
  // Inner nodes: the union of their children (which share their edges).
  for (int level = 1; level < levels; ++level) {
    const int nx = nodesAcross(level), ny = nodesDown(level);
    const int cx = nodesAcross(level - 1), cy = nodesDown(level - 1);
    heights_[size_t(level)].resize(size_t(nx) * ny);
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        glm::vec2 h(std::numeric_limits<float>::max(), std::numeric_limits<float>::lowest());
        for (int q = 0; q < 4; ++q) {
          const int ci = 2 * i + q % 2, cj = 2 * j + q / 2;
          if (ci >= cx || cj >= cy) continue;
          const glm::vec2 c = heights_[size_t(level - 1)][size_t(cj) * cx + ci];
          h = {std::min(h.x, c.x), std::max(h.y, c.y)};
        }
        heights_[size_t(level)][size_t(j) * nx + i] = h;
      }
    }
  }
}

void LodQuadtree::measureErrors(const Heightfield& field) {
  // The vertex shader reads level l's heights at level l's grid points
  // (shaders/terrain_vertex.glsl), so a patch is the triangulation of those
  // heights. Level l - 1's triangles tile level l's (both split their quads
  // north-west to south-east), so the difference of the two surfaces is
  // linear on level l - 1's triangles and largest at its vertices: a node's
  // error is the largest difference there plus its children's errors, down
  // to level 0, which is the DEM's own surface.
  const HeightMips mips(field, AAL_TERRAIN_MIP_LEVELS);
  errors_.assign(heights_.size(), {});
  errors_[0].assign(heights_[0].size(), 0.0f);
  constexpr int n = kLodPatchQuads, fine = 2 * kLodPatchQuads + 1;
  for (int level = 1; level < levels(); ++level) {
    const int nx = nodesAcross(level), ny = nodesDown(level);
    const int cx = nodesAcross(level - 1), cy = nodesDown(level - 1);
    errors_[size_t(level)].assign(size_t(nx) * ny, 0.0f);
    const double step = double(1 << level), fineStep = 0.5 * step;
    const double lastColumn = field.width - 1, lastRow = field.height - 1;
    tbb::parallel_for(0, nx * ny, [&](int node) {
      const int i = node % nx, j = node / nx;
      const double column0 = double(i) * n * step, row0 = double(j) * n * step;
      // Level l's vertex heights over the node, then level l - 1's at its
      // grid points against the triangles through them.
      std::vector<float> vertex(size_t(n + 1) * (n + 1));
      for (int b = 0; b <= n; ++b) {
        for (int a = 0; a <= n; ++a) {
          vertex[size_t(b) * (n + 1) + a] = mips.at(level, std::min(column0 + a * step, lastColumn),
                                                    std::min(row0 + b * step, lastRow));
        }
      }
      const auto v = [&](int a, int b) { return vertex[size_t(b) * (n + 1) + a]; };
      float worst = 0;
      for (int y = 0; y < fine; ++y) {
        for (int x = 0; x < fine; ++x) {
          const int a = x / 2, b = y / 2;
          const bool oddX = x % 2 != 0, oddY = y % 2 != 0;
          const float coarse = oddX && oddY ? 0.5f * (v(a, b) + v(a + 1, b + 1))  // on the diagonal
                               : oddX       ? 0.5f * (v(a, b) + v(a + 1, b))
                               : oddY       ? 0.5f * (v(a, b) + v(a, b + 1))
                                            : v(a, b);
          const float finer = mips.at(level - 1, std::min(column0 + x * fineStep, lastColumn),
                                      std::min(row0 + y * fineStep, lastRow));
          worst = std::max(worst, std::abs(coarse - finer));
        }
      }
      float children = 0;
      for (int q = 0; q < 4; ++q) {
        const int ci = 2 * i + q % 2, cj = 2 * j + q / 2;
        if (ci < cx && cj < cy) {
          children = std::max(children, errors_[size_t(level - 1)][size_t(cj) * cx + ci]);
        }
      }
      errors_[size_t(level)][size_t(node)] = worst + children;
    });
  }
}

void LodQuadtree::summarise() {
  maxDiagonalM_.clear();
  maxErrorM_.clear();
  for (int level = 0; level < levels(); ++level) {
    double worst = 0;
    for (int j = 0; j < nodesDown(level); ++j) {
      for (int i = 0; i < nodesAcross(level); ++i) {
        const LodBox b = nodeBox(level, i, j);
        worst = std::max(worst, glm::length(b.max - b.min));
      }
    }
    maxDiagonalM_.push_back(worst);
    const std::vector<float>& e = errors_[size_t(level)];
    maxErrorM_.push_back(e.empty() ? 0.0 : double(*std::max_element(e.begin(), e.end())));
  }
}

int LodQuadtree::nodesAcross(int level) const {
  return ceilDiv(ceilDiv(width_ - 1, kLodPatchQuads), 1 << level);
}

int LodQuadtree::nodesDown(int level) const {
  return ceilDiv(ceilDiv(height_ - 1, kLodPatchQuads), 1 << level);
}

glm::vec2 LodQuadtree::nodeHeights(int level, int i, int j) const {
  return heights_[size_t(level)][size_t(j) * nodesAcross(level) + i];
}

float LodQuadtree::nodeErrorM(int level, int i, int j) const {
  return errors_[size_t(level)][size_t(j) * nodesAcross(level) + i];
}

LodBox LodQuadtree::nodeBox(int level, int i, int j) const {
  const int size = nodeTexels(level);
  const int c0 = i * size, c1 = std::min(c0 + size, width_ - 1);
  const int r0 = j * size, r1 = std::min(r0 + size, height_ - 1);
  // docs/design.md §1: x east from the DEM centre, y north (row 0 is the north edge).
  const double halfW = 0.5 * (width_ - 1), halfH = 0.5 * (height_ - 1);
  const glm::vec2 h = nodeHeights(level, i, j);
  return {{(c0 - halfW) * cellXM_, (halfH - r1) * cellYM_, h.x},
          {(c1 - halfW) * cellXM_, (halfH - r0) * cellYM_, h.y}};
}

size_t LodQuadtree::memoryBytes() const {
  size_t bytes = sizeof(*this) + (maxDiagonalM_.size() + maxErrorM_.size()) * sizeof(double);
  for (const auto& level : heights_) bytes += level.capacity() * sizeof(glm::vec2);
  for (const auto& level : errors_) bytes += level.capacity() * sizeof(float);
  return bytes;
}

LodRanges makeLodRanges(const LodQuadtree& tree, double errorScale, bool morph) {
  LodRanges r;
  r.errorScale = std::max(0.0, errorScale);
  const int root = tree.levels() - 1;
  const glm::dvec2 cell = tree.cellSizeM();
  constexpr double f = kLodMorphFraction;
  double previous = 0;
  for (int level = 0; level <= root; ++level) {
    double range = kUnboundedRangeM * 4;
    if (level < root) {
      // Crack-free: D_(l-1) <= (1 - f)(range_l - range_(l-1)) (Strugar §3.2).
      range = level == 0 ? std::max(cell.x, cell.y)
                         : previous + tree.maxNodeDiagonalM(level - 1) / (1.0 - f);
      // Level l + 1 acceptable where level l starts morphing into it:
      // range_l - f (range_l - range_(l-1)) >= P e_(l+1).
      const double acceptable = r.errorScale * tree.maxErrorM(level + 1);
      range = std::max(range, (acceptable - f * previous) / (1.0 - f));
      range = std::min(range, kUnboundedRangeM);
    }
    r.rangeM.push_back(range);
    // Strugar §3.3: the morph covers the last kLodMorphFraction of the
    // level's own distance band [range_(l-1), range_l]. The root has no
    // coarser level to morph into.
    if (level == root || !morph) {
      r.morphM.emplace_back(kLodNoMorph, 2 * kLodNoMorph);
    } else {
      r.morphM.emplace_back(range - f * (range - previous), range);
    }
    previous = range;
  }
  return r;
}

double lodAutomaticErrorPixels(double viewportHeightPx) {
  return std::max(1.0, 4.0 * viewportHeightPx / 720.0);
}

double lodViewErrorScale(double viewportHeightPx, double verticalFovDeg, double maxErrorPixels) {
  // An error of e metres d metres away covers about e f / d pixels, f =
  // (H / 2) / tan(fov / 2) the focal length in pixels.
  const double focalPx = 0.5 * viewportHeightPx / std::tan(0.5 * verticalFovDeg * kPi / 180.0);
  return focalPx / maxErrorPixels;
}

double lodBudgetErrorScale(const LodQuadtree& tree, size_t triangleBudget) {
  const glm::dvec2 cell = tree.cellSizeM();
  const glm::dvec2 extent((tree.demWidth() - 1) * cell.x, (tree.demHeight() - 1) * cell.y);
  std::vector<glm::dvec3> cameras;
  for (double fy : {0.1, 0.3, 0.5, 0.7, 0.9}) {
    for (double fx : {0.1, 0.3, 0.5, 0.7, 0.9}) {
      // At the middle of its leaf's height range: inside the leaf's box.
      const int i = std::min(int(fx * tree.nodesAcross(0)), tree.nodesAcross(0) - 1);
      const int j = std::min(int(fy * tree.nodesDown(0)), tree.nodesDown(0) - 1);
      const glm::vec2 h = tree.nodeHeights(0, i, j);
      cameras.emplace_back((fx - 0.5) * extent.x, (0.5 - fy) * extent.y, 0.5 * (h.x + h.y));
    }
  }
  const auto worst = [&](double scale) {
    const LodRanges ranges = makeLodRanges(tree, scale);
    size_t most = 0;
    for (const glm::dvec3& c : cameras) {
      // Selections past the budget stop early: only "too many" matters.
      most = std::max(most, Selector(tree, ranges, c, nullptr, triangleBudget).run().triangles);
    }
    return most;
  };
  // Beyond this scale every level's range reaches past the whole DEM (or
  // no error is worth refining for): as fine as the selection gets.
  const LodBox root = tree.nodeBox(tree.levels() - 1, 0, 0);
  double smallestError = std::numeric_limits<double>::infinity();
  for (int level = 1; level < tree.levels(); ++level) {
    if (tree.maxErrorM(level) > 0) smallestError = std::min(smallestError, tree.maxErrorM(level));
  }
  if (!std::isfinite(smallestError)) return std::numeric_limits<double>::infinity();
  const double finest =
      2.0 * glm::length(root.max - root.min) / ((1.0 - kLodMorphFraction) * smallestError);
  if (worst(finest) <= triangleBudget) return std::numeric_limits<double>::infinity();
  double a = finest * 1e-6, b = finest;  // worst(a) fits, worst(b) does not
  if (worst(a) > triangleBudget) return worst(0) <= triangleBudget ? a * 1e-3 : 0;
  for (int step = 0; step < 40 && b > a * 1.001; ++step) {
    const double mid = std::sqrt(a * b);
    (worst(mid) <= triangleBudget ? a : b) = mid;
  }
  return a;
}

LodSelection selectLod(const LodQuadtree& tree, const LodRanges& ranges, glm::dvec3 cameraM,
                       const glm::mat4* viewProj) {
  LodSelection s = Selector(tree, ranges, cameraM, viewProj).run();
  s.backFacesHidden = lodHidesBackFaces(tree, cameraM);
  return s;
}

bool lodHidesBackFaces(const LodQuadtree& tree, glm::dvec3 cameraM) {
  const LodBox dem = tree.nodeBox(tree.levels() - 1, 0, 0);
  return cameraM.x >= dem.min.x && cameraM.x <= dem.max.x && cameraM.y >= dem.min.y &&
         cameraM.y <= dem.max.y && cameraM.z > dem.max.z;
}

LodSelection selectLodForFrame(const LodQuadtree& tree, const LodFrame& frame) {
  double scale = std::min(frame.budgetErrorScale,
                          lodViewErrorScale(frame.viewportHeightPx, frame.verticalFovDeg,
                                            frame.settings.maxErrorPixels > 0
                                                ? frame.settings.maxErrorPixels
                                                : lodAutomaticErrorPixels(frame.viewportHeightPx)));
  LodSelection s;
  for (int attempt = 0; attempt < 16; ++attempt) {
    s = selectLod(tree, makeLodRanges(tree, scale, frame.settings.morph), frame.cameraM,
                  &frame.viewProj);
    if (s.triangles <= frame.triangleBudget || scale <= 0) break;
    scale *= 0.8 * std::sqrt(double(frame.triangleBudget) / double(s.triangles));
    if (attempt == 14) scale = 0;  // the coarsest selection there is
  }
  s.backFacesHidden = s.backFacesHidden && frame.settings.cullBackFaces;
  return s;
}

}  // namespace aal
