#include "aperture/preprocess/openness.h"

#include <atomic>
#include <cmath>
#include <numbers>

#include <tbb/parallel_for.h>

#include "aperture/preprocess/bake_terrain.h"
#include "aperture/preprocess/horizon_sweep.h"

namespace aal {

void finishOpenness(std::vector<float>& sums, int azimuths) {
  const double toDegrees = 180.0 / std::numbers::pi;
  tbb::parallel_for(size_t(0), sums.size(), [&](size_t i) {
    sums[i] = static_cast<float>(90.0 - toDegrees * (double(sums[i]) / azimuths));
  });
}

namespace {

void checkCancel(const BakeOptions& o) {
  if (o.cancel && o.cancel->load(std::memory_order_relaxed)) throw BakeCancelled();
}

// The horizon angles of every azimuth of a bake with options `o`, summed per
// texel of the terrain's window into `sums`.
void sumHorizonAngles(const BakeTerrain& terrain, const BakeOptions& o, std::vector<float>& sums) {
  HorizonSweepOptions sweep;
  sweep.clampEdge = o.clampEdge;
  sweep.maxDistanceM = o.maxDistanceM;
  const auto addBlock = [&](const HorizonBlock& b) {
    checkCancel(o);
    for (int j = 0; j < b.count; ++j) {
      float& sum = sums[b.firstTexel + j * b.stride];
      addHorizonAngle(sum, b.tanHorizon[j]);
      if (b.tanOpposite) addHorizonAngle(sum, b.tanOpposite[j]);
    }
  };
  const double dPhi = 2.0 * std::numbers::pi / o.azimuths;
  // As the bake's own sweeps: azimuths a and a + n/2 in one pass where the
  // whole DEM counts.
  const bool opposed = o.maxDistanceM <= 0.0 && o.azimuths % 2 == 0;
  const int passes = opposed ? o.azimuths / 2 : o.azimuths;
  for (int pass = 0; pass < passes; ++pass) {
    checkCancel(o);
    const double phi = pass * dPhi;
    if (o.maxDistanceM > 0.0) {
      sweepHorizons(terrain, phi, sweep, [&](size_t texel, double tanHorizon) {
        checkCancel(o);  // one azimuth of a large DEM takes long: poll per texel too
        addHorizonAngle(sums[texel],
                        static_cast<float>(std::max(tanHorizon, double(kNoHorizonTangent))));
      });
    } else if (!opposed) {
      sweepHorizonBlocks(terrain, phi, sweep, addBlock);
    } else {
      const double opposite = (pass + passes) * dPhi;
      if (!sweepOpposedHorizonBlocks(terrain, phi, opposite, sweep, addBlock)) {
        sweepHorizonBlocks(terrain, phi, sweep, addBlock);
        sweepHorizonBlocks(terrain, opposite, sweep, addBlock);
      }
    }
    if (o.progress) o.progress(static_cast<double>(pass + 1) / passes);
  }
}

}  // namespace

std::vector<float> negativeOpenness(HeightView heights, const TexelWindow& window,
                                    const BakeOptions& o) {
  // The heights held, upside down; the voids (filled) as they are.
  std::vector<float> inverted(heights.z.size());
  tbb::parallel_for(size_t(0), inverted.size(), [&](size_t i) { inverted[i] = -heights.z[i]; });
  const HeightView invertedView(heights.dem, heights.texels, inverted, heights.voidMask);
  std::vector<float> sums(window.texelCount(), 0.0f);
  sumHorizonAngles(prepareBakeTerrain(invertedView, window), o, sums);
  finishOpenness(sums, o.azimuths);
  return sums;
}

}  // namespace aal
