// The far field's merge with the near horizons (far_horizon.h), one run of
// a block's texels that lie in one lattice cell at a time: the cell's
// bound and its four points' samples are the same along the run, so the
// AVX2 path computes 8 texels at once. Both paths give the same tangents
// bit for bit (the same single-precision operations in the same order, no
// fused multiply-adds).
#pragma once

#include <algorithm>

#include "aperture/preprocess/horizon_blocks.h"

namespace aal::detail {

struct FarCellRun {
  // The bound of the cell's far tangents (FarHorizons::cellBound): its
  // highest sample and the inverse of its nearest and farthest distances.
  float top, invNear, invFar;
  // The four points' samples, (i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1):
  // where along u, from the block's first texel (about -1e30: none), and
  // how high.
  float along[4], height[4];
  // The bilinear weight along the run at its first texel and per texel;
  // across it, the same for the whole run. alongRow: the run goes east
  // (the weight along is x's), else south.
  float wFirst, wStep, wAcross;
  bool alongRow;
  // Blend the points bilinearly; false: the largest of the four.
  bool blend;
  float halfCell, curvature;
};

// The merged tangent of the run's texel k at height z, `along` u from the
// block's first texel, with near tangent `near`.
inline float farMergedTangent(const FarCellRun& r, int k, float z, float along, float near) {
  const float rise = r.top - z;
  const float bound = rise * (rise >= 0.0f ? r.invNear : r.invFar);
  if (!(bound > near)) return near;
  float corner[4];
  for (int q = 0; q < 4; ++q) {
    const float t = r.along[q] - along;
    corner[q] = t > r.halfCell ? (r.height[q] - z) / t - r.curvature * t : kNoHorizonTangent;
  }
  const float most = std::max(std::max(corner[0], corner[1]), std::max(corner[2], corner[3]));
  const float least = std::min(std::min(corner[0], corner[1]), std::min(corner[2], corner[3]));
  const float wAlong = r.wFirst + float(k) * r.wStep;
  const float wx = r.alongRow ? wAlong : r.wAcross, wy = r.alongRow ? r.wAcross : wAlong;
  const float upper = corner[0] + (corner[1] - corner[0]) * wx;
  const float lower = corner[2] + (corner[3] - corner[2]) * wx;
  const float blended = upper + (lower - upper) * wy;
  const float far = r.blend && least > kNoHorizonTangent ? blended : most;
  return std::max(near, far);
}

#if AAL_HORIZON_AVX2
// farMergedTangent of texels 0 .. count - 1 of a run (z, along, near, merged
// hold whole vectors of 8 past count), 8 at a time (bake_avx2.cpp).
__attribute__((target("avx2"))) void mergeFarRunAvx2(const FarCellRun& r, const float* z,
                                                     const float* along, const float* near,
                                                     int count, float* merged);
#endif

}  // namespace aal::detail
