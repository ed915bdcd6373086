// Local dominance (Hesse, "Visualisation of elevation model data with local
// dominance", 2016), as the Relief Visualization Toolbox (RVT) computes it:
// how far an observer standing on a texel looks down on the land around it.
// docs/baking.md, "Local dominance".
//
// For each texel, the ring of distances d = minRadius .. maxRadius cells
// (step 1) in the azimuths 0°, 15°, ..., 345° is sampled at the nearest
// texel; an observer observerHeightM above the texel looks down on a sample
// by (z + h - z_sample) / d, counted where positive. The result is the
// mean of these, each weighted by the ring's area at its distance (2d + 1),
// divided by the same mean for a plane (h / d): 1 on a plane, above on
// peaks and ridges, below in hollows, 0 where every sample is higher than
// the observer. Distances are in cells, as RVT's: the value does not depend
// on the cell size (and on a grid with unequal cell sides the ring is an
// ellipse on the ground). Beyond the DEM the edge texels continue.
#pragma once

#include <atomic>
#include <vector>

#include "aperture/terrain/heightfield.h"

namespace aal {

struct LocalDominanceOptions {
  int minRadiusCells = 10;  // RVT's defaults
  int maxRadiusCells = 20;
  double observerHeightM = 1.7;
  // When set and true, localDominance stops and throws BakeCancelled
  // (bake.h), polled per row.
  const std::atomic<bool>* cancel = nullptr;
};

// Throws std::invalid_argument unless 1 <= minRadius <= maxRadius <= 1000
// cells and the observer height is finite and > 0.
void checkLocalDominanceOptions(const LocalDominanceOptions& options);

// One value per texel of `field` (heights in metres, voids filled), row-major.
std::vector<float> localDominance(const Heightfield& field, const LocalDominanceOptions& options);

}  // namespace aal
