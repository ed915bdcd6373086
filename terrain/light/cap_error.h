// Error of Oat's approximate cap intersection against the exact area, over a
// grid of radii and distances. Used by aal-caps and its tests.
#pragma once

#include <cstddef>
#include <vector>

namespace aal {

struct CapErrorSample {
  double r0Rad = 0, r1Rad = 0, dRad = 0;
  double exact = 0;   // steradians
  double approx = 0;  // steradians
  double absError = 0;
  double relError = 0;   // see capRelativeError
  bool partial = false;  // the caps partly overlap: the approximation is in play
};

// |approx - exact| relative to the smaller cap's area, the largest the
// intersection can be; 0 when that area is 0. (Relative to the exact area the
// error is unbounded wherever the exact area tends to 0.)
double capRelativeError(double exact, double approx, double r0Rad, double r1Rad);

// Evaluates exact and approximate areas for one configuration.
CapErrorSample evaluateCapError(double r0Rad, double r1Rad, double dRad);

// Grid sweep: r0 and r1 at `radiusSteps` values in (0, maxRadiusRad], d at
// `distanceSteps` + 1 values in [0, pi]. Order: r0 outer, then r1, then d.
std::vector<CapErrorSample> sweepCapError(int radiusSteps, int distanceSteps, double maxRadiusRad);

struct CapErrorSummary {
  double meanRelError = 0;
  double maxRelError = 0;
  size_t count = 0;  // partially overlapping samples it covers
};

// Mean and max relative error over the partially overlapping samples whose
// radii are both <= maxRadiusRad.
CapErrorSummary summarizeCapError(const std::vector<CapErrorSample>& samples, double maxRadiusRad);

}  // namespace aal
