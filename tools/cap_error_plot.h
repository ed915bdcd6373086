// Picture of the approximate cap intersection's signed relative error over
// (d, r1), one panel per r0, with axes and a colour legend.
#pragma once

#include <numbers>
#include <string>
#include <vector>

namespace aal {

struct CapErrorPlotOptions {
  std::vector<double> r0ValuesRad;  // one panel each
  double maxRadiusRad = std::numbers::pi;
  int panelPixels = 240;     // side of each panel's data area
  double colourRange = 0.2;  // legend spans [-range, +range] of the smaller cap's area
};

// Renders the plot and writes it through the image plugin (image_files.h:
// any format OpenImageIO writes; PNG recommended). Throws std::runtime_error
// when the file cannot be written or no font is available for the labels.
void writeCapErrorPlot(const std::string& path, const CapErrorPlotOptions& options);

}  // namespace aal
