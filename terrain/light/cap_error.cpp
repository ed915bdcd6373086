#include "aperture/terrain/light/cap_error.h"

#include <algorithm>
#include <cmath>

#include "aperture/terrain/light/caps.h"
#include "aperture/terrain/units.h"

namespace aal {

double capRelativeError(double exact, double approx, double r0Rad, double r1Rad) {
  const double smaller = capArea(std::min(r0Rad, r1Rad));
  return smaller > 0.0 ? std::abs(approx - exact) / smaller : 0.0;
}

CapErrorSample evaluateCapError(double r0Rad, double r1Rad, double dRad) {
  CapErrorSample s;
  s.r0Rad = r0Rad;
  s.r1Rad = r1Rad;
  s.dRad = dRad;
  s.exact = capIntersectionExact(r0Rad, r1Rad, dRad);
  s.approx = capIntersectionApprox(static_cast<float>(r0Rad), static_cast<float>(r1Rad),
                                   static_cast<float>(dRad));
  s.absError = std::abs(s.approx - s.exact);
  s.relError = capRelativeError(s.exact, s.approx, r0Rad, r1Rad);
  s.partial = dRad > std::abs(r0Rad - r1Rad) && dRad < r0Rad + r1Rad;
  return s;
}

std::vector<CapErrorSample> sweepCapError(int radiusSteps, int distanceSteps, double maxRadiusRad) {
  std::vector<CapErrorSample> samples;
  samples.reserve(static_cast<size_t>(radiusSteps) * radiusSteps * (distanceSteps + 1));
  for (int i = 1; i <= radiusSteps; ++i) {
    const double r0 = maxRadiusRad * i / radiusSteps;
    for (int j = 1; j <= radiusSteps; ++j) {
      const double r1 = maxRadiusRad * j / radiusSteps;
      for (int k = 0; k <= distanceSteps; ++k) {
        samples.push_back(evaluateCapError(r0, r1, kPi * k / distanceSteps));
      }
    }
  }
  return samples;
}

CapErrorSummary summarizeCapError(const std::vector<CapErrorSample>& samples, double maxRadiusRad) {
  CapErrorSummary summary;
  double sum = 0.0;
  for (const CapErrorSample& s : samples) {
    if (!s.partial || s.r0Rad > maxRadiusRad + 1e-12 || s.r1Rad > maxRadiusRad + 1e-12) continue;
    sum += s.relError;
    summary.maxRelError = std::max(summary.maxRelError, s.relError);
    ++summary.count;
  }
  if (summary.count > 0) summary.meanRelError = sum / static_cast<double>(summary.count);
  return summary;
}

}  // namespace aal
