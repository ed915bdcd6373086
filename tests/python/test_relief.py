"""aperture.relief against aal-relief's GeoTIFFs of the shipped DEM."""

import numpy as np
import pytest

import aperture
from aperture import rio

from conftest import JACKSBORO, run_tool


@pytest.mark.parametrize("tool_options, options", [
    ([], {}),  # 8-bit grey, sun 315 deg / 45 deg, sky 0.2
    (["--sky-only", "--format", "float"], {"sky_only": True, "format": "float"}),
    (["--multidirectional", "--sun-elevation", "30", "--mode", "exact", "--stretch", "0.2,0.9"],
     {"multidirectional": True, "sun_elevation": 30, "mode": "exact", "stretch": (0.2, 0.9)}),
    (["--time", "2024-06-21T13:00:00Z", "--no-obscurance", "--water-level", "300"],
     {"time": "2024-06-21T13:00:00Z", "obscurance": False, "water_level": 300}),
])
def test_equals_aal_relief_bit_for_bit(tmp_path, tool_env, jacksboro, tool_options, options):
    run_tool("aal-relief", JACKSBORO, "-o", tmp_path / "relief.tif", "-q", *tool_options,
             env=tool_env)
    import rasterio
    with rasterio.open(tmp_path / "relief.tif") as tif:
        expected = tif.read(1)
    dem, info = jacksboro
    picture = aperture.relief(dem, info.cell_size, **options)
    assert picture.shape == dem.shape
    assert picture.dtype == (np.float32 if options.get("format") == "float" else np.uint8)
    np.testing.assert_array_equal(picture, expected)
    assert np.unique(picture).size > 50  # a picture, not a constant


def test_time_is_lit_where_the_sun_is(jacksboro):
    dem, info = jacksboro
    when = "2024-06-21T13:00:00Z"
    # The sun of the CellSize's centre, the DEM's, as aal-relief places it.
    lat, lon = info.cell_size.center
    azimuth, elevation = aperture.solar_position(when, lat, lon)
    np.testing.assert_array_equal(
        aperture.relief(dem, info.cell_size, time=when),
        aperture.relief(dem, info.cell_size, sun_azimuth=azimuth, sun_elevation=elevation))


def test_voids_are_zero_in_bytes_and_nan_in_floats():
    y, x = np.mgrid[0:50, 0:60]
    z = (20 * np.sin(x / 5) + 10 * np.cos(y / 7)).astype(np.float32)
    z[5:9, 10:20] = np.nan
    grey = aperture.relief(z, 10.0)
    assert np.all(grey[5:9, 10:20] == 0) and np.count_nonzero(grey == 0) == 40
    value = aperture.relief(z, 10.0, format="float")
    np.testing.assert_array_equal(np.isnan(value), np.isnan(z))
    assert np.nanmin(value) >= 0 and np.nanmax(value) <= 1
