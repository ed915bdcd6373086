// Far-field horizons of a tiled bake without a max distance (docs/baking.md,
// "Far field"): beyond the reach of the near sweep, which walks each tile's
// lines only from its window (tile + halo), the terrain comes from a
// downsampled pyramid of the whole DEM (height_pyramid.h). Each line of the
// window's sweep starts with the pyramid's block maxima beyond its first
// point, in blocks that grow with their distance, in its hull: the sweep
// then sees them from every texel of the line as it sees the near terrain.
#pragma once

#include <string>
#include <vector>

#include "aperture/preprocess/bake_terrain.h"
#include "aperture/preprocess/height_pyramid.h"

namespace aal {

struct FarFieldOptions {
  // The near sweep covers at least this distance (metres) ahead of every
  // texel; the far samples start there.
  double nearReachM = 0.0;
  // Blocks no larger than 1/resolution of their distance from the texels.
  int resolution = 16;
};

// The finest pyramid level the far field reads (HeightPyramid's base
// shift): blocks of at most nearReachM / resolution. largestCellM: the
// field's largest cell.
int farFieldBaseShift(const FarFieldOptions& options, double largestCellM);
// The bake's aal:method with this far field, e.g. "sweep+far-field(max,
// reach 3840 m, lines, blocks 1/16)": resuming a folder with other
// far-field options (or a folder of the lattice far field, "lattice 16") is
// refused as a bake with other options.
std::string farFieldMethod(const FarFieldOptions& options);

struct FarField {
  const HeightPyramid* pyramid = nullptr;
  FarFieldOptions options;
};

// The far samples of the lines of azimuth phi (radians from east,
// counter-clockwise) of a window's sweep, from the window's terrain. Where a
// line's walk starts every texel it visits lies at least the near reach R
// behind, so a sample d beyond the start is at least R + d from them: it is
// read from the level whose blocks are at most (R + d) / resolution, one
// level coarser at each doubling, every half block, to the DEM's edge.
class FarLineMarch {
 public:
  FarLineMarch(const FarField& far, const BakeTerrain& terrain, double phi);

  // The samples beyond the point at field column colF, row rowF (texel
  // units, inside the DEM), nearest first: the distance beyond the point
  // along u (m) and the block's maximum (m). Clears `distance` and
  // `height` first.
  void march(double colF, double rowF, std::vector<float>& distance,
             std::vector<float>& height) const;

 private:
  const FarField& far_;
  const BakeTerrain& terrain_;
  double ux_, uy_, smallestCell_, largestCell_;
};

}  // namespace aal
