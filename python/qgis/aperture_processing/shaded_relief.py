"""Shaded relief: aal-relief, every option of its --help (docs/relief.md)."""

from qgis.PyQt.QtCore import Qt
from qgis.core import (QgsProcessingParameterBoolean, QgsProcessingParameterDateTime,
                       QgsProcessingParameterEnum, QgsProcessingParameterFile,
                       QgsProcessingParameterNumber, QgsProcessingParameterRasterDestination,
                       QgsProcessingParameterRasterLayer, QgsProcessingParameterString)

from .algorithm import ApertureAlgorithm

OUTPUT = "OUTPUT"
LIGHTINGS = (("Sun and sky", None), ("Sky only (sky-view relief)", "--sky-only"),
             ("Multidirectional suns (gdaldem's weights)", "--multidirectional"))
MODES = ("approx", "exact")
PALETTES = (("None (grey)", None), ("Hypsometric", "hypsometric"), ("Earth", "earth"))
FORMATS = ("byte", "float")
# aal-relief -of: the label in the dialog, the GDAL driver.
OUTPUT_FORMATS = (("GeoTIFF", "GTiff"), ("Cloud-optimized GeoTIFF", "COG"))
OBSCURANCE_SAMPLES = ("8", "16", "32")
OBSCURANCE_STEPS = ("1", "2")

# Optional numbers: (parameter, option, description, minimum, maximum).
OPTIONAL_NUMBERS = (
    ("SUN_AZIMUTH", "--sun-azimuth", "Sun azimuth (degrees clockwise from north; default 315)",
     -360.0, 720.0),
    ("SUN_ELEVATION", "--sun-elevation", "Sun elevation (degrees; default 45)", -90.0, 90.0),
    ("LATITUDE", "--lat", "Latitude the sun is seen from at the time (default: the DEM's centre)",
     -90.0, 90.0),
    ("LONGITUDE", "--lon", "Longitude the sun is seen from at the time (default: the DEM's centre)",
     -180.0, 180.0),
    ("SKY_WEIGHT", "--sky", "Sky weight: the sky's share of the light (default 0.2)", 0.0, 1.0),
    ("OBSCURANCE_RADIUS", "--obscurance-radius",
     "Obscurance radius (m; default 10 DEM cells)", 0.0, None),
    ("WATER_LEVEL", "--water-level", "Water level (m): heights at or below it are water", None,
     None),
    ("CELL_SIZE", "--cell-size", "Cell size (m; overrides the georeferencing)", 0.0, None),
    ("Z_SCALE", "--z-scale", "Metres per height unit (overrides the vertical unit)", 0.0, None),
)


def _number(name, description, minimum, maximum):
    parameter = QgsProcessingParameterNumber(name, description,
                                             QgsProcessingParameterNumber.Double, optional=True)
    if minimum is not None:
        parameter.setMinimum(minimum)
    if maximum is not None:
        parameter.setMaximum(maximum)
    return parameter


class ShadedReliefAlgorithm(ApertureAlgorithm):
    def name(self):
        return "shadedrelief"

    def displayName(self):  # noqa: N802
        return "Shaded relief"

    def shortHelpString(self):  # noqa: N802
        return (
            "A top-down shaded relief of the DEM with aal-relief, placed exactly like it: the sun "
            "through each cell's visible sky (soft cast shadows), sky fill and near-field "
            "obscurances. 8-bit output is 1 + 254 v like gdaldem hillshade (0 = nodata); float is "
            "v in 0..1. Without an aperture map one is baked once and cached.")

    def initAlgorithm(self, config=None):  # noqa: N802
        self.add_dem_parameter()
        self.addParameter(QgsProcessingParameterFile(
            "APERTURE", "Aperture map baked from this DEM (optional)",
            QgsProcessingParameterFile.File, "exr", optional=True))
        self.addParameter(QgsProcessingParameterString(
            "RESOLUTION", "Output pixel size: metres (30) or a scale factor (2x, 0.5x)",
            optional=True))
        self.addParameter(QgsProcessingParameterEnum(
            "LIGHTING", "Lighting", [text for text, _ in LIGHTINGS], defaultValue=0))
        self.addParameter(QgsProcessingParameterDateTime(
            "TIME", "Sun at this date and time (instead of azimuth and elevation)",
            QgsProcessingParameterDateTime.DateTime, optional=True))
        for name, option, description, minimum, maximum in OPTIONAL_NUMBERS:
            self.addParameter(_number(name, description, minimum, maximum))
        self.addParameter(QgsProcessingParameterNumber(
            "SUN_RADIUS", "Sun angular radius (degrees; larger: softer shadow edges)",
            QgsProcessingParameterNumber.Double, 0.26656, minValue=0.01, maxValue=20.0))
        self.addParameter(QgsProcessingParameterEnum(
            "MODE", "Sun and visible-sky intersection", ["Approximate (Oat's)", "Exact"],
            defaultValue=0))
        self.addParameter(QgsProcessingParameterBoolean(
            "NO_OBSCURANCE", "No near-field obscurances", False))
        self.addParameter(QgsProcessingParameterEnum(
            "OBSCURANCE_SAMPLES", "Obscurance samples", list(OBSCURANCE_SAMPLES), defaultValue=1))
        self.addParameter(QgsProcessingParameterEnum(
            "OBSCURANCE_STEPS", "Obscurance test points per ray", list(OBSCURANCE_STEPS),
            defaultValue=0))
        self.addParameter(QgsProcessingParameterEnum(
            "PALETTE", "Built-in colour ramp", [text for text, _ in PALETTES], defaultValue=0))
        self.addParameter(QgsProcessingParameterFile(
            "COLOR_RELIEF", "Colour ramp file (gdaldem color-relief's format)",
            QgsProcessingParameterFile.File, optional=True))
        self.addParameter(QgsProcessingParameterEnum(
            "FORMAT", "Grey output", ["Byte (1..255, 0 = nodata)", "Float (0..1, NaN = nodata)"],
            defaultValue=0))
        self.addParameter(QgsProcessingParameterString(
            "STRETCH", "Stretch LOW,HIGH onto the 8-bit range (e.g. 0.65,1 for sky only)",
            optional=True))
        self.addParameter(QgsProcessingParameterRasterLayer(
            "WATER_MASK", "Water mask (non-zero: water)", optional=True))
        self.addParameter(QgsProcessingParameterEnum(
            "OUTPUT_FORMAT", "File format", [label for label, _ in OUTPUT_FORMATS],
            defaultValue=0))
        self.addParameter(QgsProcessingParameterString(
            "CREATION_OPTIONS", "GDAL creation options, KEY=VALUE separated by spaces "
            "(e.g. COMPRESS=LZW)", optional=True))
        self.addParameter(QgsProcessingParameterBoolean(
            "OVERVIEWS", "Internal overviews (always with a cloud-optimized GeoTIFF)", False))
        self.addParameter(QgsProcessingParameterRasterDestination(OUTPUT, "Shaded relief"))

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        _, dem = self.dem_path(parameters, context)
        output = self.parameterAsOutputLayer(parameters, OUTPUT, context)
        arguments = [dem, "-o", output]
        for name, option in (("APERTURE", "--aperture"), ("RESOLUTION", "--resolution"),
                             ("COLOR_RELIEF", "--color-relief"), ("STRETCH", "--stretch")):
            if self.given(parameters, name):
                arguments.append(f"{option}={self.parameterAsString(parameters, name, context)}")
        lighting = LIGHTINGS[self.parameterAsEnum(parameters, "LIGHTING", context)][1]
        if lighting:
            arguments.append(lighting)
        if self.given(parameters, "TIME"):
            time = self.parameterAsDateTime(parameters, "TIME", context).toUTC()
            arguments.append(f"--time={time.toString(Qt.ISODate)}")
        for name, option, _, _, _ in OPTIONAL_NUMBERS:
            self.optional_number(parameters, name, option, context, arguments)
        arguments.append(
            f"--sun-radius={self.parameterAsDouble(parameters, 'SUN_RADIUS', context):.17g}")
        arguments.append(f"--mode={MODES[self.parameterAsEnum(parameters, 'MODE', context)]}")
        if self.parameterAsBool(parameters, "NO_OBSCURANCE", context):
            arguments.append("--no-obscurance")
        samples = self.parameterAsEnum(parameters, "OBSCURANCE_SAMPLES", context)
        steps = self.parameterAsEnum(parameters, "OBSCURANCE_STEPS", context)
        arguments += [f"--obscurance-samples={OBSCURANCE_SAMPLES[samples]}",
                      f"--obscurance-steps={OBSCURANCE_STEPS[steps]}"]
        palette = PALETTES[self.parameterAsEnum(parameters, "PALETTE", context)][1]
        if palette:
            arguments.append(f"--palette={palette}")
        arguments.append(f"--format={FORMATS[self.parameterAsEnum(parameters, 'FORMAT', context)]}")
        if self.given(parameters, "WATER_MASK"):
            mask = self.parameterAsRasterLayer(parameters, "WATER_MASK", context)
            arguments.append(f"--water-mask={mask.source()}")
        arguments.append(
            f"--of={OUTPUT_FORMATS[self.parameterAsEnum(parameters, 'OUTPUT_FORMAT', context)][1]}")
        if self.given(parameters, "CREATION_OPTIONS"):
            for option in self.parameterAsString(parameters, "CREATION_OPTIONS", context).split():
                arguments.append(f"--co={option}")
        if self.parameterAsBool(parameters, "OVERVIEWS", context):
            arguments.append("--overviews")
        self.run_tool("aal-relief", arguments, feedback)
        return {OUTPUT: output}
