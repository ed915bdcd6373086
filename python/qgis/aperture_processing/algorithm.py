"""What the aperture algorithms share: the DEM input, optional values that
become options only when given, and the tool run."""

from qgis.core import (QgsProcessingAlgorithm, QgsProcessingException,
                       QgsProcessingParameterRasterLayer)

from .tools import run_tool

INPUT = "INPUT"


class ApertureAlgorithm(QgsProcessingAlgorithm):
    """One aperture tool as a Processing algorithm. Subclasses give the
    parameters and the tool's command line."""

    def createInstance(self):  # noqa: N802 (QGIS's names)
        return type(self)()

    def group(self):
        return "Terrain lighting"

    def groupId(self):  # noqa: N802
        return "terrain_lighting"

    def add_dem_parameter(self):
        self.addParameter(QgsProcessingParameterRasterLayer(INPUT, "Elevation (DEM)"))

    def dem_path(self, parameters, context):
        """The DEM's file, as GDAL opens it: the tools read it themselves."""
        layer = self.parameterAsRasterLayer(parameters, INPUT, context)
        if layer is None:
            raise QgsProcessingException("no DEM layer given")
        if layer.providerType() != "gdal":
            raise QgsProcessingException(
                f"{layer.name()}: the aperture tools read rasters through GDAL; this layer's "
                f"provider is {layer.providerType()} (save it as a GeoTIFF first)")
        return layer, layer.source()

    @staticmethod
    def given(parameters, name):
        """Whether the optional parameter `name` has a value."""
        value = parameters.get(name)
        return value is not None and value != ""

    def optional_number(self, parameters, name, option, context, arguments):
        """`option VALUE` appended to `arguments` when `name` is given."""
        if self.given(parameters, name):
            arguments.append(f"{option}={self.parameterAsDouble(parameters, name, context):.17g}")

    def run_tool(self, tool, arguments, feedback):
        return run_tool(tool, arguments, feedback)
