// Read access to the heights held in memory for a rectangle of a DEM: every
// texel (a Heightfield) or a window of them (a HeightWindow, terrain/
// height_window.h), in the whole DEM's columns and rows. What code that
// works on either takes, such as the bake's kernels (preprocess/
// bake_terrain.h), so that one source bakes from both: at() is one index
// computation and one load, as Heightfield::at, with no call through a
// pointer.
//
// Non-owning, like std::span: valid while the Heightfield or HeightWindow
// it views lives and its z and voidMask are not resized. It is made from
// either implicitly, so a function taking a HeightView is called with
// either; a temporary is refused, since the view would outlive it.
#pragma once

#include <cstdint>
#include <span>

#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/texel_window.h"

namespace aal {

struct HeightView {
  // The whole DEM: size, metric spacing, georeferencing, nodata. Its own z
  // may be empty (demGeometry) when the view is of a window.
  const Heightfield* dem = nullptr;
  TexelWindow texels;                 // the texels held
  std::span<const float> z;           // texels.texelCount() heights, row after row, metres
  std::span<const uint8_t> voidMask;  // empty: no voids; else a flag per height, 1 = void

  HeightView() = default;
  HeightView(const Heightfield* demOf, const TexelWindow& held, std::span<const float> heights,
             std::span<const uint8_t> voids)
      : dem(demOf), texels(held), z(heights), voidMask(voids) {}
  // Every texel of `field`, the DEM itself.
  HeightView(const Heightfield& field)  // NOLINT(google-explicit-constructor): a view
      : HeightView(&field, TexelWindow{0, 0, field.width, field.height}, field.z, field.voidMask) {}
  HeightView(const Heightfield&&) = delete;

  bool holds(int x, int y) const { return texels.containsColumn(x) && texels.containsRow(y); }
  // DEM texel (x, y), which must be held.
  float at(int x, int y) const { return z[texels.index(x, y)]; }
  bool isVoid(int x, int y) const { return !voidMask.empty() && voidMask[texels.index(x, y)] != 0; }
};

}  // namespace aal
