"""Sky-view factor and visible sky: aal-bake --svf / --visible (docs/baking.md)."""

from qgis.core import (QgsProcessingException, QgsProcessingParameterBoolean,
                       QgsProcessingParameterEnum, QgsProcessingParameterFileDestination,
                       QgsProcessingParameterNumber, QgsProcessingParameterRasterDestination)

from .algorithm import ApertureAlgorithm

# The rasters aal-bake writes beside the aperture map, each a float32
# GeoTIFF placed like the DEM, its voids nodata: (parameter, aal-bake
# option, name in the dialog, written unless the user unticks it). A new
# output of aal-bake is one more line here.
BAKE_RASTER_OUTPUTS = (
    ("SKY_VIEW_FACTOR", "--svf", "Sky-view factor", True),
    ("VISIBLE_SKY", "--visible", "Visible sky fraction (Omega / 2 pi)", False),
    ("OPENNESS_POSITIVE", "--openness-positive", "Positive openness (degrees)", False),
    ("OPENNESS_NEGATIVE", "--openness-negative", "Negative openness (degrees)", False),
    ("LOCAL_DOMINANCE", "--local-dominance", "Local dominance", False),
    ("SVF_ANISOTROPIC", "--svf-anisotropic", "Anisotropic sky-view factor (RVT's low level, 315)",
     False),
    ("SKY_ILLUMINATION", "--sky-illumination", "Sky illumination (CIE overcast sky)", False),
)

AZIMUTHS = "AZIMUTHS"
MAX_DISTANCE = "MAX_DISTANCE"
EDGE = "EDGE"
CURVATURE = "CURVATURE"
APERTURE_MAP = "APERTURE_MAP"
EDGES = ("open", "clamp")


class SkyViewFactorAlgorithm(ApertureAlgorithm):
    def name(self):
        return "skyviewfactor"

    def displayName(self):  # noqa: N802
        return "Sky-view factor, openness and visible sky"

    def shortHelpString(self):  # noqa: N802
        return (
            "Bakes the visible sky of every cell of the DEM with aal-bake's horizon sweep, over "
            "the whole DEM unless a maximum distance is set, and writes the sky-view factor "
            "(Zaksek et al. 2011), the visible fraction of the sky, positive and negative "
            "openness (Yokoyama et al. 2002, degrees), local dominance (Hesse 2016, RVT's "
            "definition), the anisotropic sky-view factor (RVT's weights, low level, main "
            "direction 315 degrees) and the sky illumination under the CIE overcast sky (1 on an "
            "open horizontal plane) as float32 GeoTIFFs placed like the DEM (its voids are nodata, NaN). "
            "The aperture map (.exr or .tif, for aal-render and aal-relief) is kept only when a "
            "file is given for it.")

    def initAlgorithm(self, config=None):  # noqa: N802
        self.add_dem_parameter()
        self.addParameter(QgsProcessingParameterNumber(
            AZIMUTHS, "Azimuth directions", QgsProcessingParameterNumber.Integer, 64,
            minValue=4, maxValue=4096))
        self.addParameter(QgsProcessingParameterNumber(
            MAX_DISTANCE, "Maximum search distance (m, 0: the whole DEM)",
            QgsProcessingParameterNumber.Double, 0.0, minValue=0.0))
        self.addParameter(QgsProcessingParameterEnum(
            EDGE, "Beyond the DEM's edge", ["Open sky", "Flat terrain at the edge height"],
            defaultValue=0))
        self.addParameter(QgsProcessingParameterBoolean(
            CURVATURE, "Drop distant terrain by the Earth's curvature", False))
        for name, _, description, by_default in BAKE_RASTER_OUTPUTS:
            self.addParameter(QgsProcessingParameterRasterDestination(
                name, description, optional=True, createByDefault=by_default))
        self.addParameter(QgsProcessingParameterFileDestination(
            APERTURE_MAP, "Aperture map", "OpenEXR (*.exr);;GeoTIFF (*.tif)", optional=True,
            createByDefault=False))

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        _, dem = self.dem_path(parameters, context)
        arguments = [dem]
        results = {}
        for name, option, _, _ in BAKE_RASTER_OUTPUTS:
            path = self.parameterAsOutputLayer(parameters, name, context) \
                if self.given(parameters, name) else ""
            if path:
                arguments.append(f"{option}={path}")
                results[name] = path
        if not results:
            raise QgsProcessingException(
                "no output chosen: choose at least one of " +
                ", ".join(description for _, _, description, _ in BAKE_RASTER_OUTPUTS))
        # Without a map asked for, aal-bake writes the rasters alone and sums
        # no aperture map: about a fifth faster.
        aperture = self.parameterAsFileOutput(parameters, APERTURE_MAP, context) \
            if self.given(parameters, APERTURE_MAP) else ""
        if aperture:
            arguments += ["-o", aperture]
            results[APERTURE_MAP] = aperture
        arguments += [
            f"--azimuths={self.parameterAsInt(parameters, AZIMUTHS, context)}",
            f"--max-distance={self.parameterAsDouble(parameters, MAX_DISTANCE, context):.17g}",
            f"--edge={EDGES[self.parameterAsEnum(parameters, EDGE, context)]}",
        ]
        if self.parameterAsBool(parameters, CURVATURE, context):
            arguments.append("--curvature")
        self.run_tool("aal-bake", arguments, feedback)
        return results
