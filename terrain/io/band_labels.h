// What each band of the GeoTIFFs the tools write is, in the words GIS tools
// show as the band's name (GDALSetDescription) and its unit: declared once,
// so that aal-bake's whole-DEM and tiled outputs, and the aperture map as
// GeoTIFF, name them alike.
#pragma once

#include <array>

#include "aperture/terrain/io/geotiff_writer.h"

namespace aal {

// aal-bake --svf (Zaksek et al., "Sky-view factor as a relief visualization
// technique", 2011): dimensionless, 0..1.
inline RasterBandLabel skyViewFactorBandLabel() {
  return {"sky-view factor", ""};
}

// aal-bake --visible: the visible solid angle over 2 pi, 0..1.
inline RasterBandLabel visibleFractionBandLabel() {
  return {"visible sky fraction (solid angle / 2 pi)", ""};
}

// aal-bake --openness-positive and --openness-negative (Yokoyama, Shirasawa
// and Pike, "Visualizing topography by openness", 2002): degrees, 90 on a
// plane.
inline RasterBandLabel positiveOpennessBandLabel() {
  return {"positive openness (deg)", "deg"};
}
inline RasterBandLabel negativeOpennessBandLabel() {
  return {"negative openness (deg)", "deg"};
}

// aal-bake --local-dominance (Hesse, "Visualisation of elevation model data
// with local dominance", 2016, as RVT computes it): 1 on a plane.
inline RasterBandLabel localDominanceBandLabel() {
  return {"local dominance", ""};
}

// aal-bake --svf-anisotropic (Zaksek, Ostir and Kokalj 2011, RVT's
// weights): dimensionless, 0..1.
inline RasterBandLabel anisotropicSkyViewFactorBandLabel() {
  return {"anisotropic sky-view factor", ""};
}

// aal-bake --sky-illumination: diffuse irradiance under the sky model over
// that of a horizontal plane under the open sky, 1 there.
inline RasterBandLabel skyIlluminationBandLabel(bool overcast) {
  return {overcast ? "sky illumination (CIE overcast sky, 1 = open horizontal plane)"
                   : "sky illumination (uniform sky, 1 = open horizontal plane)",
          ""};
}

// aal-relief's grey or float relief.
inline RasterBandLabel reliefBandLabel(bool bytes) {
  return {bytes ? "shaded relief (1 + 254 v, 0 = nodata)" : "shaded relief (0..1)", ""};
}

// The aperture map's four bands (terrain/io/aperture_map.h): the unit bent
// normal in the world frame, then the cap's arc length.
inline std::array<RasterBandLabel, 4> apertureMapBandLabels() {
  return {{{"bent normal x (east)", ""},
           {"bent normal y (north)", ""},
           {"bent normal z (up)", ""},
           {"aperture arc length (rad)", "rad"}}};
}

}  // namespace aal
