"""The screenshots of docs/gis.md: QGIS with the Aperture provider, run by
scripts/qgis-screenshots.sh inside QGIS (qgis --code) under Xvfb.

Bakes the sky-view factor and positive openness of the shipped DEM through the
provider's algorithm, adds both as layers, and saves the Processing dialog
and the map window as PNG files into $APERTURE_SHOTS."""
import os
import sys

from qgis.core import QgsApplication, QgsProject, QgsRasterLayer
from qgis.PyQt.QtCore import QTimer
from qgis.utils import iface

sys.path.insert(0, os.path.join(os.environ["APERTURE_SOURCE"], "python", "qgis"))
from aperture_processing.provider import ApertureProvider  # noqa: E402

import processing  # noqa: E402

shots = os.environ["APERTURE_SHOTS"]
dem = os.path.join(os.environ["APERTURE_SOURCE"], "heightmaps", "jacksboro_fault_dem.tif")
provider = ApertureProvider()
QgsApplication.processingRegistry().addProvider(provider)
outputs = {"SKY_VIEW_FACTOR": os.path.join(shots, "svf.tif"),
           "OPENNESS_POSITIVE": os.path.join(shots, "openness.tif")}
parameters = {"INPUT": dem, "AZIMUTHS": 32, **outputs}


def grab(widget, name):
    widget.grab().save(os.path.join(shots, name))


def dialog_shot():
    dialog = processing.createAlgorithmDialog("aperture:skyviewfactor", parameters)
    dialog.resize(900, 640)
    dialog.show()
    QTimer.singleShot(1500, lambda: (grab(dialog, "qgis-processing-dialog.png"), dialog.close(),
                                     run_and_show()))


def run_and_show():
    processing.run("aperture:skyviewfactor", parameters)
    # The last added is drawn on top: openness.
    for key, title in (("SKY_VIEW_FACTOR", "sky-view factor"),
                       ("OPENNESS_POSITIVE", "positive openness")):
        QgsProject.instance().addMapLayer(QgsRasterLayer(outputs[key], title))
    iface.mainWindow().resize(1280, 800)
    iface.mapCanvas().zoomToFullExtent()
    QTimer.singleShot(4000, lambda: (grab(iface.mainWindow(), "qgis-openness-layer.png"),
                                     QgsApplication.exit(0)))


iface.mainWindow().resize(1280, 800)
QTimer.singleShot(2000, dialog_shot)
