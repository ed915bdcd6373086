// The sample set of the containment-test obscurance estimator
// (docs/design.md §6; Umenhoffer et al., "Efficient Methods for Ambient
// Lighting", 2009, §4.1, eq. 8): n well-spread points (ξx, ξy, ξz) of the unit
// cube, mapped to cosine-distributed directions and to distances with the
// density μ'(r) of the fuzzy membership μ(d) = sqrt(d/R).
//
// The points are a Poisson-disc-like set made by Lloyd relaxation (as in
// Umenhoffer et al. 2009, which samples "from the Poisson disc distribution"):
// Voronoi cells of the unit cube, periodic in ξx because it is the azimuth,
// estimated from a fixed low-discrepancy set of candidate points. Everything is
// deterministic and computed once per n (memoised, thread-safe).
#pragma once

#include <vector>

#include <glm/vec3.hpp>

namespace aal {

// n = 8, 16 or 32 (AAL_OBSCURANCE_MAX_SAMPLES is the largest).
bool isSupportedObscuranceSampleCount(int n);

// The n relaxed points in [0, 1)^3. Throws std::invalid_argument for an
// unsupported n.
const std::vector<glm::vec3>& obscuranceUnitCubePoints(int n);

// Umenhoffer et al. 2009, eq. 8, for one point of the unit cube: the direction
// ω = T cos(2πξx)√ξy + B sin(2πξx)√ξy + N√(1-ξy) (cosine distributed) times
// the distance r/R = ξz² (μ⁻¹(ξz) for μ(d) = sqrt(d/R)). Returned as (X, Y, Z)
// along (T, B, N) in units of the radius R.
glm::vec3 obscuranceOffset(glm::vec3 xi);

// obscuranceOffset of every point of obscuranceUnitCubePoints(n).
const std::vector<glm::vec3>& obscuranceSampleOffsets(int n);

// Interleaved sampling (Umenhoffer et al. 2009, §4.2; Keller & Heidrich 2001)
// gives each of the 16 cells of the 4x4 pixel pattern its own set: the relaxed
// points under a Cranley-Patterson rotation (Cranley & Patterson 1976), a
// toroidal shift s_k of the unit cube, so cell k uses frac(ξ + s_k).
// s_k.x = k/16 is the azimuth rotation 2πk/16 about N; (s_k.y, s_k.z) also
// move the elevations and distances, which rotations alone leave shared by all
// 16 cells (docs/obscurance.md). Cell 0 is the unshifted set.
constexpr int kObscuranceSampleSets = 16;

// The 16 shifts s_k of the n-point set, s_0 = 0 (see the .cpp for how
// (s_k.y, s_k.z) are chosen). Throws std::invalid_argument for an
// unsupported n.
const std::vector<glm::vec3>& obscuranceCellShifts(int n);

// Cell k's points frac(ξ + s_k) and their offsets (obscuranceOffset); cell 0
// equals obscuranceUnitCubePoints(n) / obscuranceSampleOffsets(n). Throws
// std::invalid_argument for an unsupported n or k outside 0..15.
const std::vector<glm::vec3>& obscuranceCellUnitCubePoints(int n, int cell);
const std::vector<glm::vec3>& obscuranceCellSampleOffsets(int n, int cell);

// Spread of a point set of the unit cube, for the tests and docs/obscurance.md.
// Smallest distance between two points, with ξx periodic (the azimuth wraps).
double minimumPeriodicDistance(const std::vector<glm::vec3>& points);
// L2 star discrepancy by Warnock's closed form (Warnock 1972); a uniform
// random set of n points has E[T²] = (2^-3 - 3^-3) / n.
double l2StarDiscrepancy(const std::vector<glm::vec3>& points);
// Wrap-around L2 discrepancy (Hickernell 1998): the L2* measure over boxes of
// the torus, so unchanged by a toroidal shift (every interleave cell's set has
// the base set's); a uniform random set of n points has
// E[WD²] = ((3/2)^3 - (4/3)^3) / n.
double wrapAroundL2Discrepancy(const std::vector<glm::vec3>& points);

}  // namespace aal
