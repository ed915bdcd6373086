#include "aperture/tools/cap_error_plot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "aperture/terrain/io/atomic_file.h"
#include "aperture/terrain/io/image_files.h"
#include "aperture/terrain/light/caps.h"
#include "aperture/terrain/units.h"

namespace aal {

namespace {

constexpr int kMarginLeft = 70, kMarginTop = 40, kMarginBottom = 60, kGap = 40;
constexpr int kLegendWidth = 24, kLegendMargin = 110;

using Colour = std::array<float, 3>;

std::string findFont() {
  for (const char* candidate :
       {"/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf", "/usr/share/fonts/TTF/DejaVuSans.ttf",
        "/usr/share/fonts/dejavu/DejaVuSans.ttf"}) {
    if (std::filesystem::exists(candidate)) return candidate;
  }
  throw std::runtime_error(
      "no font for the plot labels: install fonts-dejavu-core (scripts/install-deps.sh)");
}

// Diverging blue-white-red colour for t in [-1, 1] (negative: approximation too small).
Colour divergingColour(double t) {
  t = std::clamp(t, -1.0, 1.0);
  const Colour blue{0.13f, 0.35f, 0.75f}, white{0.97f, 0.97f, 0.97f}, red{0.80f, 0.15f, 0.12f};
  const Colour& end = t < 0 ? blue : red;
  const float a = static_cast<float>(std::abs(t));
  return {white[0] + a * (end[0] - white[0]), white[1] + a * (end[1] - white[1]),
          white[2] + a * (end[2] - white[2])};
}

// RGB floats, rows top to bottom.
struct Picture {
  int width, height;
  std::vector<float> rgb;

  Picture(int w, int h) : width(w), height(h), rgb(static_cast<size_t>(w) * h * 3) {}
  void set(int x, int y, const Colour& c) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    std::copy(c.begin(), c.end(), rgb.begin() + (static_cast<size_t>(y) * width + x) * 3);
  }
};

// Pixels [x0, x1) x [y0, y1) (set() clips to the picture).
void fillRect(Picture& image, int x0, int y0, int x1, int y1, const Colour& c) {
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) image.set(x, y, c);
  }
}

class Labeller {
 public:
  Labeller(Picture& image, std::string font) : image_(image), font_(std::move(font)) {}
  void text(int x, int y, const std::string& s, int size, TextAlign align = TextAlign::Left) {
    try {
      drawText(image_.rgb.data(), image_.width, image_.height, x, y, s, size, font_, {0, 0, 0},
               align);
    } catch (const ImageFileError& e) {
      throw std::runtime_error(std::string("cannot render plot text: ") + e.what());
    }
  }

 private:
  Picture& image_;
  std::string font_;
};

std::string formatNumber(const char* format, double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, format, value);
  return buffer;
}

void drawPanel(Picture& image, Labeller& label, int left, int top, double r0,
               const CapErrorPlotOptions& o) {
  const int n = o.panelPixels;
  // Data: x = d in [0, pi], y = r1 in [0, maxRadius] (bottom to top).
  for (int py = 0; py < n; ++py) {
    const double r1 = o.maxRadiusRad * (n - py - 0.5) / n;
    for (int px = 0; px < n; ++px) {
      const double d = kPi * (px + 0.5) / n;
      const double exact = capIntersectionExact(r0, r1, d);
      const double approx = capIntersectionApprox(static_cast<float>(r0), static_cast<float>(r1),
                                                  static_cast<float>(d));
      const double scale = capArea(std::min(r0, r1));
      const double signedError = scale > 0 ? (approx - exact) / scale : 0.0;
      const Colour c = divergingColour(signedError / o.colourRange);
      image.set(left + px, top + py, c);
    }
  }
  const Colour black{0, 0, 0};
  fillRect(image, left - 1, top - 1, left + n + 1, top, black);
  fillRect(image, left - 1, top + n, left + n + 1, top + n + 1, black);
  fillRect(image, left - 1, top, left, top + n, black);
  fillRect(image, left + n, top, left + n + 1, top + n, black);

  label.text(left + n / 2, top - 10, "r0 = " + formatNumber("%.0f", degrees(r0)) + " deg", 18,
             TextAlign::Center);
  for (int deg = 0; deg <= 180; deg += 45) {  // d axis ticks
    const int x = left + static_cast<int>(std::lround(n * deg / 180.0));
    fillRect(image, x, top + n, x + 1, top + n + 6, black);
    label.text(x, top + n + 22, std::to_string(deg), 14, TextAlign::Center);
  }
  label.text(left + n / 2, top + n + 44, "d (degrees)", 15, TextAlign::Center);
  const double maxDeg = degrees(o.maxRadiusRad);
  for (int i = 0; i <= 4; ++i) {  // r1 axis ticks
    const double deg = maxDeg * i / 4;
    const int y = top + n - static_cast<int>(std::lround(n * i / 4.0));
    fillRect(image, left - 6, y, left, y + 1, black);
    label.text(left - 9, y + 5, formatNumber("%.0f", deg), 14, TextAlign::Right);
  }
  label.text(left - 62, top + n / 2 - 5, "r1", 15);
  label.text(left - 62, top + n / 2 + 13, "(deg)", 12);
}

void drawLegend(Picture& image, Labeller& label, int left, int top, int height, double range) {
  for (int py = 0; py < height; ++py) {
    const double t = 1.0 - 2.0 * (py + 0.5) / height;
    fillRect(image, left, top + py, left + kLegendWidth, top + py + 1, divergingColour(t));
  }
  for (int i = 0; i <= 4; ++i) {
    const double value = range * (1.0 - 0.5 * i);
    const int y = top + static_cast<int>(std::lround(height * i / 4.0));
    fillRect(image, left + kLegendWidth, y, left + kLegendWidth + 5, y + 1, {0, 0, 0});
    label.text(left + kLegendWidth + 8, y + 5,
               value == 0 ? std::string("0%") : formatNumber("%+.0f%%", value * 100), 14);
  }
  label.text(left - 4, top - 10, "error", 14);
}

}  // namespace

void writeCapErrorPlot(const std::string& path, const CapErrorPlotOptions& options) {
  if (options.r0ValuesRad.empty()) throw std::invalid_argument("plot needs at least one r0");
  const int panels = static_cast<int>(options.r0ValuesRad.size());
  const int columns = std::min(panels, 2);
  const int rows = (panels + columns - 1) / columns;
  const int n = options.panelPixels;
  const int width =
      kMarginLeft + columns * n + (columns - 1) * (kGap + kMarginLeft - 30) + kLegendMargin;
  const int titleHeight = 50;
  const int height = titleHeight + rows * (kMarginTop + n + kMarginBottom);

  Picture image(width, height);
  fillRect(image, 0, 0, width, height, {1, 1, 1});
  Labeller label(image, findFont());
  label.text(width / 2, 30,
             "Oat's approximate cap intersection: (approx - exact) / area of smaller cap", 17,
             TextAlign::Center);

  for (int i = 0; i < panels; ++i) {
    const int col = i % columns, row = i / columns;
    const int left = kMarginLeft + col * (n + kGap + kMarginLeft - 30);
    const int top = titleHeight + kMarginTop + row * (kMarginTop + n + kMarginBottom);
    drawPanel(image, label, left, top, options.r0ValuesRad[i], options);
  }
  drawLegend(image, label, width - kLegendMargin + 20, titleHeight + kMarginTop,
             rows * (kMarginTop + n + kMarginBottom) - kMarginTop - kMarginBottom,
             options.colourRange);

  AtomicOutput output(path);
  try {
    writeImageFile(output.temporaryPath().string(), width, height, 3, image.rgb.data(),
                   /*eightBit=*/true);
  } catch (const ImageFileError& e) {
    throw output.failure(e.what(), "plot");
  }
  output.commit();
}

}  // namespace aal
