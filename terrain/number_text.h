// A number as messages print it: up to 10 significant digits, no trailing
// zeros ("0.3", "1e+300", "nan"), so that a value the user gave reads back
// as given.
#pragma once

#include <cstdio>
#include <string>

namespace aal {

inline std::string numberText(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.10g", value);
  return text;
}

}  // namespace aal
