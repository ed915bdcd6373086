// The sample set of the containment-test obscurance estimator (DESIGN §6;
// seed 000 §4.1, eq. 8): n well-spread points (ξx, ξy, ξz) of the unit cube,
// mapped to cosine-distributed directions and to distances with the density
// μ'(r) of the fuzzy membership μ(d) = sqrt(d/R).
//
// The points are a Poisson-disc-like set made by Lloyd relaxation (as in seed
// 000, which samples "from the Poisson disc distribution"): Voronoi cells of
// the unit cube, periodic in ξx because it is the azimuth, estimated from a
// fixed low-discrepancy set of candidate points. Everything is deterministic
// and computed once per n (memoised, thread-safe).
#pragma once

#include <vector>

#include <glm/vec3.hpp>

namespace aal {

// n = 8, 16 or 32 (AAL_OBSCURANCE_MAX_SAMPLES is the largest).
bool isSupportedObscuranceSampleCount(int n);

// The n relaxed points in [0, 1)^3. Throws std::invalid_argument for an
// unsupported n.
const std::vector<glm::vec3>& obscuranceUnitCubePoints(int n);

// Seed 000 eq. 8 for one point of the unit cube: the direction
// ω = T cos(2πξx)√ξy + B sin(2πξx)√ξy + N√(1-ξy) (cosine distributed) times
// the distance r/R = ξz² (μ⁻¹(ξz) for μ(d) = sqrt(d/R)). Returned as (X, Y, Z)
// along (T, B, N) in units of the radius R.
glm::vec3 obscuranceOffset(glm::vec3 xi);

// obscuranceOffset of every point of obscuranceUnitCubePoints(n).
const std::vector<glm::vec3>& obscuranceSampleOffsets(int n);

// Spread of a point set of the unit cube, for the tests and docs/obscurance.md.
// Smallest distance between two points, with ξx periodic (the azimuth wraps).
double minimumPeriodicDistance(const std::vector<glm::vec3>& points);
// L2 star discrepancy by Warnock's closed form (Warnock 1972); a uniform
// random set of n points has E[T²] = (2^-3 - 3^-3) / n.
double l2StarDiscrepancy(const std::vector<glm::vec3>& points);

}  // namespace aal
