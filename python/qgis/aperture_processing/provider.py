"""The Processing provider "Aperture": the algorithms and the setting that
names the folder of the tools."""

from qgis.core import QgsProcessingProvider

from .render_view import RenderViewAlgorithm
from .shaded_relief import ShadedReliefAlgorithm
from .sky_view_factor import SkyViewFactorAlgorithm
from .tools import BIN_DIR_SETTING


class ApertureProvider(QgsProcessingProvider):
    def id(self):
        return "aperture"

    def name(self):
        return "Aperture"

    def longName(self):  # noqa: N802 (QGIS's names)
        return "Aperture terrain lighting (aal-bake, aal-relief, aal-render)"

    def load(self):
        try:
            from processing.core.ProcessingConfig import ProcessingConfig, Setting
        except ImportError:  # QGIS without its Processing plugin: PATH and $APERTURE_BIN_DIR
            return super().load()
        ProcessingConfig.addSetting(Setting(
            self.name(), BIN_DIR_SETTING,
            "Folder of the aperture tools (empty: beside the plugin's install prefix, or PATH)",
            "", valuetype=Setting.FOLDER))
        ProcessingConfig.readSettings()
        self.refreshAlgorithms()
        return True

    def unload(self):
        try:
            from processing.core.ProcessingConfig import ProcessingConfig
        except ImportError:
            return
        ProcessingConfig.removeSetting(BIN_DIR_SETTING)

    def loadAlgorithms(self):  # noqa: N802
        for algorithm in (SkyViewFactorAlgorithm(), ShadedReliefAlgorithm(),
                          RenderViewAlgorithm()):
            self.addAlgorithm(algorithm)

    def supportedOutputRasterLayerExtensions(self):  # noqa: N802
        # The tools write GeoTIFF whatever the name.
        return ["tif"]

    def defaultRasterFileExtension(self):  # noqa: N802
        return "tif"
