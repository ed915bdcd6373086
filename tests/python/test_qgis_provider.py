"""The QGIS Processing provider (python/qgis/aperture_processing; docs/gis.md,
"QGIS") run headless: its algorithms through processing.run on a small
GeoTIFF, and Cancel stopping a long bake. Skipped where python3-qgis is not
installed."""

import math
import os
import sys
import time

import numpy as np
import pytest

from conftest import BIN_DIR, SOURCE_DIR, hills

qgis_core = pytest.importorskip("qgis.core")

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
# QGIS's own plugins (processing) and ours, from the source tree.
sys.path.insert(0, "/usr/share/qgis/python/plugins")
sys.path.insert(0, str(SOURCE_DIR / "python" / "qgis"))

EPSG = 32616
NODATA = -9999.0
ORIGIN = (500000.0, 4000000.0)
CELL = 30.0


@pytest.fixture(scope="module")
def qgis_app():
    """QgsApplication without a display, Processing and our provider."""
    qgs = qgis_core.QgsApplication([], False)
    qgs.initQgis()
    from processing.core.Processing import Processing
    Processing.initialize()
    from aperture_processing.provider import ApertureProvider
    provider = ApertureProvider()
    assert qgis_core.QgsApplication.processingRegistry().addProvider(provider)
    yield qgs
    qgis_core.QgsApplication.processingRegistry().removeProvider(provider)


@pytest.fixture(autouse=True)
def tools_environment(monkeypatch, tmp_path):
    monkeypatch.setenv("APERTURE_BIN_DIR", str(BIN_DIR))
    monkeypatch.setenv("AAL_CACHE_DIR", str(tmp_path / "cache"))


def write_dem(path, heights, voids=()):
    """A float32 GeoTIFF in UTM 16N with 30 m cells, NODATA at `voids`."""
    from osgeo import gdal, osr
    heights = heights.copy()
    for row, col in voids:
        heights[row, col] = NODATA
    rows, cols = heights.shape
    dataset = gdal.GetDriverByName("GTiff").Create(str(path), cols, rows, 1, gdal.GDT_Float32)
    dataset.SetGeoTransform((ORIGIN[0], CELL, 0, ORIGIN[1], 0, -CELL))
    srs = osr.SpatialReference()
    srs.ImportFromEPSG(EPSG)
    dataset.SetProjection(srs.ExportToWkt())
    band = dataset.GetRasterBand(1)
    band.SetNoDataValue(NODATA)
    band.WriteArray(heights)
    dataset = None
    return path


def files_in(folder):
    """The files in `folder`, less the .aux.xml that QGIS writes beside a
    raster it opens."""
    return sorted(p.name for p in folder.iterdir() if not p.name.endswith(".aux.xml"))


def temporary_maps():
    """The aperture maps in Processing's temporary folder."""
    import pathlib
    return sorted(pathlib.Path(qgis_core.QgsProcessingUtils.tempFolder()).rglob("*.exr"))


def raster_layer(path):
    layer = qgis_core.QgsRasterLayer(str(path), path.name, "gdal")
    assert layer.isValid(), path
    return layer


def test_provider_lists_the_algorithms(qgis_app):
    registry = qgis_core.QgsApplication.processingRegistry()
    for name in ("skyviewfactor", "shadedrelief", "renderview"):
        assert registry.algorithmById(f"aperture:{name}") is not None, name


def test_sky_view_factor_is_placed_like_the_dem(qgis_app, tmp_path):
    import processing
    dem = write_dem(tmp_path / "dem.tif", hills(48, 64), voids=[(10, 20), (30, 5)])
    svf, visible = tmp_path / "svf.tif", tmp_path / "visible.tif"
    openness = tmp_path / "openness.tif"
    progress = []
    feedback = qgis_core.QgsProcessingFeedback()
    feedback.progressChanged.connect(progress.append)
    result = processing.run("aperture:skyviewfactor", {
        "INPUT": str(dem), "AZIMUTHS": 16, "MAX_DISTANCE": 0, "EDGE": 0,
        "SKY_VIEW_FACTOR": str(svf), "VISIBLE_SKY": str(visible),
        "OPENNESS_POSITIVE": str(openness),
    }, feedback=feedback)
    assert result["SKY_VIEW_FACTOR"] == str(svf)
    assert progress and progress[-1] == pytest.approx(100.0)
    source = raster_layer(dem)
    for path in (svf, visible):
        out = raster_layer(path)
        assert out.crs().authid() == f"EPSG:{EPSG}"
        assert out.crs() == source.crs()
        assert out.extent() == source.extent()
        assert (out.width(), out.height()) == (source.width(), source.height())
        # The input's voids are the output's nodata: NaN, a float raster's
        # own (GDAL's convention), not the DEM's integer value.
        provider = out.dataProvider()
        assert provider.sourceHasNoDataValue(1)
        assert math.isnan(provider.sourceNoDataValue(1))
        from osgeo import gdal
        values = gdal.Open(str(path)).ReadAsArray()
        assert math.isnan(values[10, 20]) and math.isnan(values[30, 5])
        valid = values[~np.isnan(values)]
        assert valid.size == 48 * 64 - 2
        assert ((valid > 0) & (valid <= 1)).all()
    # Openness, degrees: placed alike; with the open edge its outer ring has
    # no angle in some direction and is nodata too (docs/baking.md).
    out = raster_layer(openness)
    assert out.crs() == source.crs() and out.extent() == source.extent()
    from osgeo import gdal
    values = gdal.Open(str(openness)).ReadAsArray()
    assert math.isnan(values[10, 20]) and math.isnan(values[0, 7])
    inner = values[1:-1, 1:-1]
    valid = inner[~np.isnan(inner)]
    assert valid.size == 46 * 62 - 2
    assert ((valid > 45) & (valid < 135)).all()
    # No aperture map asked for: none kept, here or in the temporary folder.
    assert files_in(tmp_path) == ["dem.tif", "openness.tif", "svf.tif", "visible.tif"]
    assert temporary_maps() == []


def test_sky_illumination_and_anisotropic_svf_are_placed_like_the_dem(qgis_app, tmp_path):
    import processing
    from osgeo import gdal
    dem = write_dem(tmp_path / "dem.tif", hills(48, 64), voids=[(10, 20)])
    asvf, sky = tmp_path / "asvf.tif", tmp_path / "sky.tif"
    result = processing.run("aperture:skyviewfactor", {
        "INPUT": str(dem), "AZIMUTHS": 16, "MAX_DISTANCE": 0, "EDGE": 0,
        "SKY_VIEW_FACTOR": None, "SVF_ANISOTROPIC": str(asvf), "SKY_ILLUMINATION": str(sky),
    })
    assert result["SVF_ANISOTROPIC"] == str(asvf) and result["SKY_ILLUMINATION"] == str(sky)
    source = raster_layer(dem)
    for path, band in ((asvf, "anisotropic sky-view factor"),
                       (sky, "sky illumination (CIE overcast sky, 1 = open horizontal plane)")):
        out = raster_layer(path)
        assert out.crs() == source.crs() and out.extent() == source.extent()
        dataset = gdal.Open(str(path))
        assert dataset.GetRasterBand(1).GetDescription() == band
        values = dataset.ReadAsArray()
        assert math.isnan(values[10, 20])
        valid = values[~np.isnan(values)]
        assert valid.size == 48 * 64 - 1
        # Hills: darker than an open plane somewhere, never brighter.
        assert ((valid > 0) & (valid <= 1 + 1e-6)).all() and valid.min() < 0.99
    assert files_in(tmp_path) == ["asvf.tif", "dem.tif", "sky.tif"]


def test_sky_view_factor_sums_no_map_unless_one_is_asked_for(qgis_app, tmp_path, monkeypatch):
    import processing
    from aperture_processing import algorithm
    command_lines = []
    monkeypatch.setattr(algorithm.ApertureAlgorithm, "run_tool",
                        lambda self, tool, arguments, feedback: command_lines.append(arguments))
    dem = write_dem(tmp_path / "dem.tif", hills(16, 16))
    outputs = {"INPUT": str(dem), "SKY_VIEW_FACTOR": str(tmp_path / "svf.tif")}
    processing.run("aperture:skyviewfactor", outputs)
    processing.run("aperture:skyviewfactor", {**outputs, "APERTURE_MAP": str(tmp_path / "a.exr")})
    # The rasters alone: aal-bake without -o, which sums no aperture map.
    alone, with_map = command_lines
    assert "-o" not in alone
    assert with_map[with_map.index("-o") + 1] == str(tmp_path / "a.exr")


def test_sky_view_factor_without_an_output_is_refused(qgis_app, tmp_path):
    import processing
    dem = write_dem(tmp_path / "dem.tif", hills(16, 16))
    with pytest.raises(qgis_core.QgsProcessingException):
        processing.run("aperture:skyviewfactor", {"INPUT": str(dem)})


def test_cancel_stops_the_bake_and_leaves_no_output(qgis_app, tmp_path):
    import processing
    # Tens of seconds of baking on this machine, were it not canceled.
    dem = write_dem(tmp_path / "dem.tif", hills(512, 512))
    svf, aperture = tmp_path / "svf.tif", tmp_path / "aperture.exr"
    feedback = qgis_core.QgsProcessingFeedback()
    canceled_at = []

    def cancel_on_first_report(_):
        if not canceled_at:
            canceled_at.append(time.monotonic())
            feedback.cancel()

    feedback.progressChanged.connect(cancel_on_first_report)
    start = time.monotonic()
    with pytest.raises(qgis_core.QgsProcessingException):
        processing.run("aperture:skyviewfactor", {
            "INPUT": str(dem), "AZIMUTHS": 4096, "SKY_VIEW_FACTOR": str(svf),
            "APERTURE_MAP": str(aperture),
        }, feedback=feedback)
    ended = time.monotonic()
    assert canceled_at, "no progress was reported before the bake ended"
    assert ended - canceled_at[0] < 5.0, f"stopped {ended - canceled_at[0]:.1f} s after Cancel"
    assert ended - start < 30.0
    assert not svf.exists() and not aperture.exists()
    assert files_in(tmp_path) == ["dem.tif"]
    assert temporary_maps() == []


def test_shaded_relief_is_placed_like_the_dem(qgis_app, tmp_path):
    import processing
    dem = write_dem(tmp_path / "dem.tif", hills(40, 56))
    output = tmp_path / "relief.tif"
    processing.run("aperture:shadedrelief", {
        "INPUT": str(dem), "LIGHTING": 1, "FORMAT": 1, "SUN_RADIUS": 0.5,
        "OUTPUT": str(output)})
    out, source = raster_layer(output), raster_layer(dem)
    assert out.crs() == source.crs() and out.extent() == source.extent()
    from osgeo import gdal
    values = gdal.Open(str(output)).ReadAsArray()
    assert values.shape == (40, 56) and values.dtype == np.float32
    assert np.isfinite(values).all() and (values > 0).all() and (values <= 1).all()


def test_render_view_writes_the_image(qgis_app, tmp_path):
    import processing
    dem = write_dem(tmp_path / "dem.tif", hills(48, 64))
    output = tmp_path / "view.png"
    source = raster_layer(dem)
    extent = source.extent()
    processing.run("aperture:renderview", {
        "INPUT": str(dem), "WIDTH": 64, "HEIGHT": 40, "TIME": "2024-06-21T15:00:00Z",
        "EXTENT": f"{extent.xMinimum()},{extent.center().x()},{extent.yMinimum()},"
                  f"{extent.center().y()} [EPSG:{EPSG}]",
        "BACKGROUND": 1, "OUTPUT": str(output)})
    from osgeo import gdal
    image = gdal.Open(str(output))
    assert (image.RasterXSize, image.RasterYSize, image.RasterCount) == (64, 40, 4)
    alpha = image.GetRasterBand(4).ReadAsArray()
    # The camera looks at the area's centre: terrain there (opaque), and
    # the sky above the horizon transparent.
    assert (alpha[16:24, 28:36] == 255).all()
    assert (alpha[0] == 0).any()


def help_options(tool):
    """The long options a tool's --help lists, and its help text."""
    import re
    import subprocess
    text = subprocess.run([str(BIN_DIR / tool), "--help"], capture_output=True, text=True,
                          check=True).stdout
    return set(re.findall(r"^\s+(?:-\w,)?(--[a-z-]+)", text, re.MULTILINE)), text


def test_shaded_relief_offers_every_option_of_aal_relief(qgis_app, tmp_path, monkeypatch):
    import processing
    from aperture_processing import algorithm, shaded_relief
    command_lines = []
    monkeypatch.setattr(algorithm.ApertureAlgorithm, "run_tool",
                        lambda self, tool, arguments, feedback: command_lines.append(arguments))
    dem = write_dem(tmp_path / "dem.tif", hills(16, 16))
    mask = write_dem(tmp_path / "mask.tif", np.zeros((16, 16), np.float32))
    ramp = tmp_path / "ramp.txt"
    ramp.write_text("0 0 0 0\n1000 255 255 255\n")
    common = {"INPUT": str(dem), "RESOLUTION": "2x", "SUN_RADIUS": 1.0, "SKY_WEIGHT": 0.3,
              "OBSCURANCE_RADIUS": 50, "OBSCURANCE_SAMPLES": 2, "OBSCURANCE_STEPS": 1,
              "FORMAT": 1, "STRETCH": "0.1,0.9", "OUTPUT_FORMAT": 1,
              "CREATION_OPTIONS": "COMPRESS=LZW BIGTIFF=YES", "OVERVIEWS": True, "CELL_SIZE": 30, "Z_SCALE": 1,
              "NO_OBSCURANCE": True, "MODE": 1, "OUTPUT": str(tmp_path / "r.tif")}
    # The options that exclude each other, one of each pair per run.
    processing.run("aperture:shadedrelief", {
        **common, "LIGHTING": 1, "PALETTE": 1, "WATER_LEVEL": 300,
        "TIME": "2024-06-21T12:00:00Z", "LATITUDE": 36, "LONGITUDE": -84})
    processing.run("aperture:shadedrelief", {
        **common, "LIGHTING": 2, "COLOR_RELIEF": str(ramp), "WATER_MASK": str(mask),
        "SUN_AZIMUTH": 200, "SUN_ELEVATION": 20, "APERTURE": str(tmp_path / "a.exr")})
    given = {argument.split("=")[0] for line in command_lines for argument in line
             if argument.startswith("--")}
    listed, text = help_options("aal-relief")
    assert len(listed) > 25, listed
    # What the plugin sets itself (-o, --progress), has no use for, or gives
    # in other words (--cog is -of COG).
    assert listed - {"--help", "--version", "--quiet", "--output", "--progress", "--cog"} <= given, \
        listed - given
    # Every built-in palette --palette names.
    import re
    listed_palettes = re.search(r"--palette TEXT\s+built-in colour ramp[^:]*: ([a-z, ]+)", text)
    assert listed_palettes, text
    assert {value for _, value in shaded_relief.PALETTES if value} == \
        {name.strip() for name in listed_palettes.group(1).split(",")}
