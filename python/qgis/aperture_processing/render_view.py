"""Render a view: aal-render of an area of the DEM from a direction, at a
date and time (docs/rendering.md)."""

import json
import math
import subprocess

from qgis.PyQt.QtCore import Qt
from qgis.core import (QgsPointXY, QgsProcessingException, QgsProcessingParameterDateTime,
                       QgsProcessingParameterEnum, QgsProcessingParameterExtent,
                       QgsProcessingParameterFileDestination, QgsProcessingParameterNumber)

from .algorithm import ApertureAlgorithm
from .tools import tool_path

OUTPUT = "OUTPUT"
MODES = ("approx", "exact", "baseline-ao", "baseline-lambert", "reference")
BACKGROUNDS = ("sky", "transparent")


def dem_geometry(dem):
    """aal-info --json of the DEM: its size in texels, its cells in metres,
    its height range and z scale, as the tools read them."""
    result = subprocess.run([tool_path("aal-info"), "--json", dem], capture_output=True,
                            text=True, check=False)
    if result.returncode != 0:
        raise QgsProcessingException(f"aal-info {dem}: {result.stderr.strip()}")
    return json.loads(result.stdout)


def to_dem_frame(layer, info, point):
    """A point of the layer's CRS in the DEM frame (x east, y north, metres
    from the DEM's centre; docs/design.md, section 1): the offset from the
    layer's centre in cells, times the cells' size in metres."""
    extent = layer.extent()
    step_x = extent.width() / info["width"]
    step_y = extent.height() / info["height"]
    cell_x, cell_y = info["cell_size_m"]
    centre = extent.center()
    return ((point.x() - centre.x()) / step_x * cell_x,
            (point.y() - centre.y()) / step_y * cell_y)


class RenderViewAlgorithm(ApertureAlgorithm):
    def name(self):
        return "renderview"

    def displayName(self):  # noqa: N802
        return "Render a view"

    def shortHelpString(self):  # noqa: N802
        return (
            "A perspective image of the DEM with aal-render, lit by the sun and the sky at a date "
            "and time (or a sun azimuth and elevation): the camera looks at the centre of the "
            "area from the given direction and elevation angle, far enough away for the whole "
            "area to fit the field of view. PNG for display, EXR for linear radiance. Without "
            "an aperture map one is baked once and cached.")

    def initAlgorithm(self, config=None):  # noqa: N802
        self.add_dem_parameter()
        self.addParameter(QgsProcessingParameterExtent(
            "EXTENT", "Area to view (default: the whole DEM)", optional=True))
        self.addParameter(QgsProcessingParameterNumber(
            "VIEW_AZIMUTH", "Camera direction: seen from (degrees clockwise from north)",
            QgsProcessingParameterNumber.Double, 135.0, minValue=-360.0, maxValue=720.0))
        self.addParameter(QgsProcessingParameterNumber(
            "VIEW_ELEVATION", "Camera elevation angle above the area (degrees)",
            QgsProcessingParameterNumber.Double, 35.0, minValue=1.0, maxValue=89.0))
        self.addParameter(QgsProcessingParameterNumber(
            "FOV", "Vertical field of view (degrees)", QgsProcessingParameterNumber.Double, 40.0,
            minValue=1.0, maxValue=170.0))
        self.addParameter(QgsProcessingParameterDateTime(
            "TIME", "Date and time (the sun's position; default: azimuth and elevation below)",
            QgsProcessingParameterDateTime.DateTime, optional=True))
        for name, option, description, low, high in (
                ("SUN_AZIMUTH", "--sun-azimuth", "Sun azimuth (degrees; default 315)", -360, 720),
                ("SUN_ELEVATION", "--sun-elevation", "Sun elevation (degrees; default 45)", -90,
                 90)):
            self.addParameter(QgsProcessingParameterNumber(
                name, description, QgsProcessingParameterNumber.Double, optional=True,
                minValue=low, maxValue=high))
        self.addParameter(QgsProcessingParameterEnum(
            "MODE", "Shading", list(MODES), defaultValue=0))
        self.addParameter(QgsProcessingParameterNumber(
            "WIDTH", "Image width (pixels)", QgsProcessingParameterNumber.Integer, 1280,
            minValue=1, maxValue=65536))
        self.addParameter(QgsProcessingParameterNumber(
            "HEIGHT", "Image height (pixels)", QgsProcessingParameterNumber.Integer, 720,
            minValue=1, maxValue=65536))
        self.addParameter(QgsProcessingParameterNumber(
            "EXAGGERATION", "Vertical exaggeration", QgsProcessingParameterNumber.Double, 1.0,
            minValue=0.01, maxValue=100.0))
        self.addParameter(QgsProcessingParameterEnum(
            "BACKGROUND", "Background", ["Sky", "Transparent"], defaultValue=0))
        self.addParameter(QgsProcessingParameterFileDestination(
            OUTPUT, "Image", "PNG (*.png);;OpenEXR, linear (*.exr)"))

    def camera(self, parameters, context, layer, dem, width, height):
        """--camera and --look-at for the area and the direction, for an
        image of width x height pixels."""
        info = dem_geometry(dem)
        area = self.parameterAsExtent(parameters, "EXTENT", context, layer.crs()) \
            if self.given(parameters, "EXTENT") else layer.extent()
        if area.isEmpty():
            area = layer.extent()
        x0, y0 = to_dem_frame(layer, info, QgsPointXY(area.xMinimum(), area.yMinimum()))
        x1, y1 = to_dem_frame(layer, info, QgsPointXY(area.xMaximum(), area.yMaximum()))
        target_x, target_y = (x0 + x1) / 2, (y0 + y1) / 2
        exaggeration = self.parameterAsDouble(parameters, "EXAGGERATION", context)
        z_low, z_high = info["z_min"] * exaggeration, info["z_max"] * exaggeration
        target_z = (z_low + z_high) / 2
        # Far enough that the area fits: across, its half diagonal within
        # half the horizontal field of view; up and down, its depth as seen
        # from the elevation angle, and its relief, within half the vertical.
        elevation = math.radians(self.parameterAsDouble(parameters, "VIEW_ELEVATION", context))
        half_vertical = math.radians(self.parameterAsDouble(parameters, "FOV", context)) / 2
        half_horizontal = math.atan(math.tan(half_vertical) * width / height)
        radius = max(0.5 * math.hypot(x1 - x0, y1 - y0), 1.0)
        depth = radius * math.sin(elevation) + 0.5 * (z_high - z_low) * math.cos(elevation)
        distance = 1.05 * max(radius / math.tan(half_horizontal), depth / math.tan(half_vertical))
        azimuth = math.radians(self.parameterAsDouble(parameters, "VIEW_AZIMUTH", context))
        camera = (target_x + distance * math.cos(elevation) * math.sin(azimuth),
                  target_y + distance * math.cos(elevation) * math.cos(azimuth),
                  target_z + distance * math.sin(elevation))
        return (f"--camera={camera[0]:.3f},{camera[1]:.3f},{camera[2]:.3f}",
                f"--look-at={target_x:.3f},{target_y:.3f},{target_z:.3f}")

    def processAlgorithm(self, parameters, context, feedback):  # noqa: N802
        layer, dem = self.dem_path(parameters, context)
        output = self.parameterAsFileOutput(parameters, OUTPUT, context)
        width = self.parameterAsInt(parameters, "WIDTH", context)
        height = self.parameterAsInt(parameters, "HEIGHT", context)
        arguments = [dem, "-o", output, f"--size={width}x{height}",
                     *self.camera(parameters, context, layer, dem, width, height),
                     f"--fov={self.parameterAsDouble(parameters, 'FOV', context):.17g}",
                     f"--mode={MODES[self.parameterAsEnum(parameters, 'MODE', context)]}",
                     f"--exaggeration="
                     f"{self.parameterAsDouble(parameters, 'EXAGGERATION', context):.17g}",
                     f"--background="
                     f"{BACKGROUNDS[self.parameterAsEnum(parameters, 'BACKGROUND', context)]}"]
        if self.given(parameters, "TIME"):
            time = self.parameterAsDateTime(parameters, "TIME", context).toUTC()
            arguments.append(f"--time={time.toString(Qt.ISODate)}")
        self.optional_number(parameters, "SUN_AZIMUTH", "--sun-azimuth", context, arguments)
        self.optional_number(parameters, "SUN_ELEVATION", "--sun-elevation", context, arguments)
        self.run_tool("aal-render", arguments, feedback)
        return {OUTPUT: output}
