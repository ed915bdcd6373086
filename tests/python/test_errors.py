"""Bad input raises ValueError (TypeError for wrong types) with a message naming what is
wrong -- the library's own, as the tools print it -- and never takes the interpreter down."""

import math

import numpy as np
import pytest

import aperture

GOOD = np.zeros((8, 9), dtype=np.float32)


@pytest.mark.parametrize("dem, cell_size, options, message", [
    (np.zeros(10), 1.0, {}, "dem must be a 2-D array"),
    (np.zeros((2, 3, 4)), 1.0, {}, "dem must be a 2-D array"),
    (np.zeros((0, 5)), 1.0, {}, "dem is empty"),
    (np.zeros((5, 0)), 1.0, {}, "dem is empty"),
    (np.zeros((4, 4), dtype=complex), 1.0, {}, "dem must hold real numbers"),
    (np.array([["a", "b"], ["c", "d"]]), 1.0, {}, "dem must hold real numbers"),
    (np.zeros((4, 4), dtype=bool), 1.0, {}, "dem must hold real numbers"),
    (np.full((6, 6), np.nan), 1.0, {}, "dem: every texel is void (nodata); nothing to use"),
    (np.ma.MaskedArray(GOOD, mask=True), 1.0, {}, "every texel is void"),
    (np.full((3, 3), 5.0), 1.0, {"nodata": 5}, "every texel is void"),
    (np.full((3, 3), 2e6), 1.0, {}, "is beyond any terrain"),
    (np.zeros((1, 70000), dtype=np.float32), 1.0, {}, "dem"),
    (GOOD, 0.0, {}, "cell_size: the x spacing must be in [1e-06, 10000000] metres, got 0"),
    (GOOD, -1.0, {}, "cell_size: the x spacing must be in"),
    (GOOD, math.nan, {}, "cell_size: the x spacing must be in"),
    (GOOD, (1.0, math.inf), {}, "cell_size: the y spacing must be in"),
    (GOOD, aperture.CellSize(1.0, 1.0, np.ones(3)), {}, "one per row"),
    (GOOD, aperture.CellSize(1.0, 1.0, -np.ones(8)), {}, "every row's x spacing"),
    (GOOD, 1.0, {"azimuths": 0}, "azimuths must be in [4, 4096]"),
    (GOOD, 1.0, {"azimuths": 5000}, "azimuths must be in [4, 4096]"),
    (GOOD, 1.0, {"azimuths": 2**40}, "azimuths is out of range"),
    (GOOD, 1.0, {"max_distance": -5.0}, "max distance must be >= 0"),
    (GOOD, 1.0, {"max_distance": math.nan}, "max distance must be >= 0"),
    (GOOD, 1.0, {"edge": "wrap"}, "edge must be 'open' or 'clamp'"),
    (GOOD, 1.0, {"refraction": 1.5}, "refraction coefficient must be in [0, 1)"),
    (GOOD, 1.0, {"horizons": 5}, "horizon directions must be 4, 8, 12 or 16"),
    (GOOD, 1.0, {"horizons": 12}, "directional horizons need the sweep with a multiple of 12"),
    (GOOD, 1.0, {"threads": 0}, "threads must be a positive integer"),
    (GOOD, 1.0, {"z_scale": -1.0}, "z_scale must be a positive number"),
])
def test_bake_refuses_bad_input_with_value_error(dem, cell_size, options, message):
    with pytest.raises(ValueError) as error:
        aperture.bake(dem, cell_size, **options)
    assert message in str(error.value)


@pytest.mark.parametrize("cell_size, options", [
    ("10", {}),
    (None, {}),
    ((1.0, 2.0, 3.0), {}),
    (1.0, {"azimuths": 64.0}),
    (1.0, {"progress": 5}),
    (1.0, {"nodata": "x"}),
])
def test_wrong_types_raise_type_error(cell_size, options):
    with pytest.raises(TypeError):
        aperture.bake(GOOD, cell_size, **options)


@pytest.mark.parametrize("options, message", [
    ({"format": "png"}, "format must be 'byte' or 'float'"),
    ({"sky_only": True, "sun_azimuth": 10}, "sky_only has no sun"),
    ({"time": "2024-06-21T12:00Z", "sun_elevation": 10}, "give time or sun_azimuth"),
    ({"lat": 10}, "lat and lon place the sun for time"),
    ({"multidirectional": True, "sun_azimuth": 10}, "multidirectional lights from"),
    ({"time": "yesterday"}, "time must be ISO 8601"),
    ({"sun_elevation": 95}, "sun_elevation must be in [-90, 90] degrees, got 95"),
    ({"sky": 2}, "sky must be in [0, 1]"),
    ({"stretch": (0.5, 0.2)}, "stretch must be (low, high) with 0 <= low < high <= 1"),
    ({"format": "float", "stretch": (0, 0.5)}, "stretch is for 8-bit output"),
    ({"mode": "fast"}, "mode must be 'approx' or 'exact'"),
    ({"obscurance_samples": 7}, "--obscurance-samples must be 8, 16 or 32, got 7"),
])
def test_relief_refuses_bad_options(options, message):
    with pytest.raises(ValueError) as error:
        aperture.relief(GOOD, 1.0, **options)
    assert message in str(error.value)


def test_relief_needs_a_surface():
    with pytest.raises(ValueError, match="1 x 9 texels have no surface to render"):
        aperture.relief(np.zeros((9, 1)), 1.0)


@pytest.mark.parametrize("options, message", [
    ({"size": (0, 10)}, "size must be (width, height) with sides in [1, 65536]"),
    ({"size": "big"}, "size must be (width, height)"),
    ({"mode": "nice"}, "mode must be one of approx, baseline-ao"),
    ({"camera": (1, 2)}, "camera must be (x, y, z)"),
    ({"camera": (1, 2, 3), "look_at": (1, 2, 3)}, "camera and look_at are the same point"),
    ({"fov": 0}, "fov must be in [1, 170] degrees"),
    ({"background": "black"}, "background must be 'sky' or 'transparent'"),
    ({"albedo": (1, 2, 3)}, "albedo must be A or (R, G, B) with values in [0, 1]"),
    ({"exaggeration": 0}, "exaggeration must be in [0.01, 100]"),
    ({"anisotropy": 5}, "anisotropy must be 1 to 4 probes, got 5"),
    ({"supersample": 0}, "supersample must be 1 to 4 points per pixel and axis, got 0"),
    ({"time": "2024-13-01T00:00Z"}, "time must be ISO 8601"),
])
def test_render_refuses_bad_options_before_any_work(options, message):
    with pytest.raises(ValueError) as error:
        aperture.render(GOOD, 1.0, **options)
    assert message in str(error.value)


def test_solar_position_refuses_bad_input():
    with pytest.raises(ValueError, match="when must be a datetime or ISO 8601"):
        aperture.solar_position("noon", 0, 0)
    with pytest.raises(ValueError, match="lat must be in"):
        aperture.solar_position("2024-06-21T12:00Z", 91, 0)
    with pytest.raises(TypeError):
        aperture.solar_position(12.0, 0, 0)


def test_metric_cell_size_refuses_what_the_dem_reader_refuses():
    with pytest.raises(ValueError, match="rotated or sheared grid"):
        aperture.metric_cell_size("EPSG:4326", (0, 0.1, 0.01, 0, 0, -0.1), 10, 10)
    with pytest.raises(ValueError, match="beyond"):
        aperture.metric_cell_size("EPSG:4326", (0, 1, 0, 89, 0, -1), 10, 200)
    with pytest.raises(ValueError, match="not a CRS"):
        aperture.metric_cell_size("no such crs", (0, 1, 0, 0, 0, -1), 10, 10)
    with pytest.raises(ValueError, match="geocentric"):
        aperture.metric_cell_size("EPSG:4978", (0, 1, 0, 0, 0, -1), 10, 10)
