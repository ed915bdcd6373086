// Far-field horizons of a tiled bake without a max distance (docs/baking.md,
// "Far field"): beyond the reach of the near sweep, which walks each tile's
// lines only from its window (tile + halo), the horizon comes from a
// downsampled pyramid of the whole DEM (height_pyramid.h), marched along
// each azimuth in blocks that grow with distance. It varies slowly across a
// tile, so it is marched from a coarse lattice of points and interpolated.
#pragma once

#include <string>
#include <vector>

#include "aperture/preprocess/bake_terrain.h"
#include "aperture/preprocess/height_pyramid.h"
#include "aperture/preprocess/horizon_blocks.h"

namespace aal {

struct FarFieldOptions {
  // The near sweep covers at least this distance (metres) ahead of every
  // texel; the far march starts here, less the lattice's spacing.
  double nearReachM = 0.0;
  // Lattice points every `spacing` texels of the window.
  int spacing = 16;
  // Blocks no larger than 1/resolution of their distance.
  int resolution = 16;
  // Heights of blocks: their maxima (a horizon never below the terrain's)
  // or, for an estimate, their means interpolated bilinearly.
  bool meanHeights = false;
  // A texel takes the largest of its four lattice points' horizons rather
  // than their bilinear blend.
  bool maxOfCorners = false;
};

// Where the far march starts: the near reach less the lattice's spacing
// (a texel is up to spacing * sqrt 2 cells from its lattice points), at
// least one cell. smallestCellM, largestCellM: the field's cell sizes.
double farMarchStartM(const FarFieldOptions& options, double smallestCellM, double largestCellM);
// The finest pyramid level the march reads (HeightPyramid's base shift).
int farFieldBaseShift(const FarFieldOptions& options, double smallestCellM, double largestCellM);
// The bake's aal:method with this far field, e.g. "sweep+far-field(max,
// reach 3840 m, lattice 16, blocks 1/16)": resuming a folder with other
// far-field options is refused as a bake with other options.
std::string farFieldMethod(const FarFieldOptions& options);

struct FarField {
  const HeightPyramid* pyramid = nullptr;
  FarFieldOptions options;
};

// The far horizons of one azimuth phi (radians from east, counter-clockwise)
// at the lattice points of the terrain's window. `curvature` is the drop
// coefficient k (drop = k t^2, 1/m) as in HorizonSweepOptions.
class FarHorizons {
 public:
  FarHorizons(const FarField& far, const BakeTerrain& terrain, double phi, double curvature,
              bool clampEdge);

  // Tangent of the far horizon seen from field texel (col, row) of the
  // window at height z; kNoHorizon (horizon_sweep.h) when none.
  double tangentAt(int col, int row, double z) const;
  // max(nearTangent, tangentAt(col, row, z)), skipping the far field where
  // a bound of it over the texel's lattice cell is no higher.
  double mergedTangent(int col, int row, double z, double nearTangent) const;
  // mergedTangent of each texel of a block of the window's block sweep
  // (sweepWindowHorizonBlocks: window indices along a row or a column,
  // open edges, so this FarHorizons' clampEdge must be false), as floats,
  // into merged[0 .. b.count).
  void mergeBlock(const HorizonBlock& b, float* merged) const;

 private:
  // The highest sample seen from a lattice point: its height z (before the
  // curvature drop) and distance t along u from the point; t = 0: none.
  // Where the march left the DEM: the edge's height and distance. A texel
  // near the point sees the same samples from its own place: its distance
  // to them is t less its offset along u from the point.
  struct Point {
    double x = 0.0, y = 0.0;  // the point's position
    double z = 0.0, t = 0.0;
    double edgeZ = 0.0, edgeT = -1.0;  // edgeT < 0: no edge
    // The sample's place along u: t plus the point's (x, y) . u. A texel at
    // (x, y) is along - (x, y) . u from it, one subtraction per point.
    double along = 0.0;
  };
  // The tangent to p's sample from a texel at height z whose place along u
  // is (x, y) . u.
  double pointTangent(const Point& p, double along, double z) const;
  double tangentAt(int col, int row, double along, double z) const;
  Point march(const BakeTerrain& terrain, int col, int row) const;

  // Per lattice cell (the four points around it): the highest sample's
  // height and the nearest and farthest samples' distances from any of its
  // texels, for a bound of their far tangents; kNoHorizon height: none.
  struct CellBound {
    double z = 0.0, invNear = 0.0, invFar = 0.0;
    // The four points' samples, (i, j), (i + 1, j), (i, j + 1), (i + 1,
    // j + 1), side by side for mergeBlock's loops over them: where along u
    // and how high (without an edge; -infinity along: no sample).
    double along[4], z4[4];
  };
  double cellBound(const CellBound& c, double z) const;

  // The lattice cell of a texel `offset` texels into the window (>= 0).
  int latticeIndex(int offset) const {
    return spacingShift_ >= 0 ? offset >> spacingShift_ : offset / far_.options.spacing;
  }

  const FarField& far_;
  const BakeTerrain& terrain_;
  double smallestCell_, largestCell_;  // over the DEM's rows
  double ux_, uy_, curvature_;
  bool clampEdge_;
  int spacingShift_ = -1;  // log2 of the lattice's spacing, or -1: not a power of two
  int originCol_, originRow_, columns_, rows_;
  std::vector<Point> points_;
  std::vector<CellBound> bounds_;  // (columns_ - 1) x (rows_ - 1)
};

}  // namespace aal
