// Deterministic synthetic terrain (fBm or ridged value noise) for tests,
// benchmarks and scripts that need DEMs of any size without shipping data.
#pragma once

#include <cstdint>

#include "aperture/terrain/heightfield.h"

namespace aal {

struct SyntheticTerrainOptions {
  int width = 256, height = 256;
  double cellSizeM = 30.0;
  uint64_t seed = 1;
  double amplitudeM = 600.0;  // peak-to-peak relief, roughly
  // Wavelength of the largest features, in texels. Each octave halves it.
  double featureSizeTexels = 128.0;
  int octaves = 7;
  bool ridged = false;  // sharp ridges (1 - |noise|) instead of rounded hills
};

// Same options, same heights, on every machine (integer hashing, no libm
// randomness). Heights are >= 0, in metres; format = "synthetic".
Heightfield makeSyntheticTerrain(const SyntheticTerrainOptions& options);

}  // namespace aal
