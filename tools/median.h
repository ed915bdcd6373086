// The median of a tool's timings (aal-view --stats, aal-render
// --pass-profile): the middle value, or the mean of the two middle ones.
#pragma once

#include <algorithm>
#include <vector>

namespace aal {

// `values` must not be empty.
inline double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
}

}  // namespace aal
