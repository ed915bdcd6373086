"""The aperture Processing provider as a QGIS plugin (docs/gis.md, "QGIS")."""


def classFactory(iface):  # noqa: N802 (the name QGIS calls)
    from .plugin import AperturePlugin

    return AperturePlugin(iface)
