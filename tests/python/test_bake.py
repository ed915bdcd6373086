"""aperture.bake and sky_view_factor against aal-bake, closed forms and voids."""

import json
import math

import numpy as np
import pytest

import aperture
from aperture import rio

from conftest import JACKSBORO, hills, run_tool


def test_equals_aal_bake_bit_for_bit_on_the_shipped_dem(tmp_path, jacksboro, tool_env):
    run_tool("aal-bake", JACKSBORO, "-o", tmp_path / "a.exr", "--svf", tmp_path / "svf.tif",
             "--visible", tmp_path / "visible.tif", "-q", env=tool_env)
    svf, _ = rio.read(tmp_path / "svf.tif")
    visible, _ = rio.read(tmp_path / "visible.tif")

    dem, info = jacksboro
    result = aperture.bake(dem, info.cell_size)
    assert result.visible.dtype == np.float32 and result.visible.shape == dem.shape
    assert np.isfinite(result.visible).all() and np.isfinite(result.sky_view_factor).all()
    np.testing.assert_array_equal(result.visible, visible)
    np.testing.assert_array_equal(result.sky_view_factor, svf)
    # Not a trivial equality: the sky is occluded in the valleys.
    assert result.sky_view_factor.min() < 0.9
    np.testing.assert_array_equal(aperture.sky_view_factor(dem, info.cell_size), svf)


def test_rio_gives_the_cell_size_aal_info_reports(jacksboro):
    info_json = json.loads(run_tool("aal-info", JACKSBORO, "--json").stdout)
    dem, info = jacksboro
    x, y = info_json["cell_size_m"]
    assert info.cell_size.x == pytest.approx(x, rel=1e-8)
    assert info.cell_size.y == pytest.approx(y, rel=1e-8)
    assert info.cell_size.center == pytest.approx(
        (info_json["center_lat"], info_json["center_lon"]), abs=1e-8)
    # A geographic grid: the x spacing of each row, narrowing northwards.
    rows = info.cell_size.rows
    assert rows.shape == (dem.shape[0],)
    assert np.all(np.diff(rows) > 0)
    assert rows[0] < x < rows[-1]
    # A uniform spacing is another DEM for the bake: the per-row spacing counts.
    uniform = aperture.bake(dem, (info.cell_size.x, info.cell_size.y))
    assert not np.array_equal(uniform.sky_view_factor,
                              aperture.bake(dem, info.cell_size).sky_view_factor)


def test_voids_equal_aal_bake_with_nodata(tmp_path, tool_env):
    z = hills(80, 100)
    z[30:42, 20:45] = -9999.0  # a void block, filled by the nearest height
    z[0, :7] = -9999.0  # and one on the edge
    from rasterio.transform import from_origin
    placed = rio.RasterInfo(100, 80, "EPSG:32616", from_origin(500000, 4000000, 30, 30),
                            -9999.0, None, 1.0, "float32", {})
    rio.write(tmp_path / "dem.tif", z, like=placed, nodata=-9999.0)
    run_tool("aal-bake", tmp_path / "dem.tif", "-o", tmp_path / "a.exr", "--svf",
             tmp_path / "svf.tif", "--visible", tmp_path / "visible.tif", "-q", env=tool_env)
    svf, svf_info = rio.read(tmp_path / "svf.tif")
    visible, _ = rio.read(tmp_path / "visible.tif")
    assert np.isnan(svf_info.nodata)  # aal-bake marks voids NaN, never the DEM's -9999

    dem, info = rio.read(tmp_path / "dem.tif")
    assert info.cell_size.x == info.cell_size.y == 30.0 and info.cell_size.rows is None
    result = aperture.bake(dem, info.cell_size)
    np.testing.assert_array_equal(result.visible, visible)  # NaN where the tool has nodata
    np.testing.assert_array_equal(result.sky_view_factor, svf)
    assert np.isnan(result.sky_view_factor).sum() == 12 * 25 + 7


def test_a_flat_plane_sees_the_whole_sky():
    for shape, cell in (((40, 50), 5.0), ((7, 300), (2.0, 30.0)), ((1, 1), 1.0)):
        result = aperture.bake(np.zeros(shape), cell)
        assert np.all(result.visible == 1.0)
        assert np.all(result.sky_view_factor == 1.0)
        assert np.all(result.arc_length == np.float32(math.pi / 2))
        # Up, to the rounding of the sum of the azimuths' unit vectors (3e-18 here).
        np.testing.assert_allclose(result.bent_normal, np.broadcast_to([0, 0, 1], shape + (3,)),
                                   rtol=0, atol=1e-6)


def _trench(beta_deg=30.0, width=201, height=301, cell=2.0):
    """A V-trench along north-south: z = |x| tan(beta), floor on the middle column."""
    x = (np.arange(width) - width // 2) * cell
    return np.tile(np.abs(x) * math.tan(math.radians(beta_deg)), (height, 1))


def test_v_trench_sky_view_factor_has_its_closed_form():
    """SVF = 1 - mean_phi sin(max(h(phi), 0)) of a V-trench with walls at slope angle beta.

    Floor: looking at azimuth phi (from east, across the trench at phi = 0) every point
    of a wall lies at elevation h(phi) = atan(tan(beta) |cos(phi)|), so with a = tan(beta)
        SVF = 1 - (2/pi) int_0^{pi/2} a cos(phi) / sqrt(1 + a^2 cos^2(phi)) dphi
            = 1 - (2/pi) arcsin(sin(beta)) = 1 - 2 beta / pi,
    whatever the trench's length or width (beta = 30 deg: 2/3).

    Side, x0 metres up-slope from the floor: uphill (cos(phi) < 0 towards its own wall)
    h = atan(a |cos(phi)|) again; across, the far wall's elevation atan(a (cos(phi) -
    2 x0 / t)) grows with the distance t, up to the DEM's edge t_max(phi), so
        h(phi) = atan(a (cos(phi) - 2 x0 / t_max(phi)))  (1 - 2 beta / pi as t_max -> inf).
    The bake sums its azimuths k 2 pi / 64 (the trapezoidal rule), so the closed forms
    are compared both in that sum (to 1e-4) and, for the floor, integrated (to 5e-4).
    """
    beta, cell, width, height = math.radians(30.0), 2.0, 201, 301
    a = math.tan(beta)
    result = aperture.bake(_trench(30.0, width, height, cell), cell, azimuths=64)
    svf = result.sky_view_factor
    row, floor = height // 2, width // 2
    phis = np.arange(64) * 2 * math.pi / 64

    closed = 1 - 2 * beta / math.pi
    in_the_sum = 1 - np.mean(np.sin(np.arctan(a * np.abs(np.cos(phis)))))
    assert svf[row, floor] == pytest.approx(in_the_sum, abs=1e-4)
    assert svf[row, floor] == pytest.approx(closed, abs=5e-4)
    # The horizontal floor's visible fraction is its sky-view factor.
    assert result.visible[row, floor] == pytest.approx(svf[row, floor], abs=1e-6)

    half_x, half_y = floor * cell, (height // 2) * cell
    for steps in (5, 20, 50, 90):
        x0 = steps * cell
        horizons = []
        for phi in phis:
            c, s = math.cos(phi), math.sin(phi)
            if c <= 0:  # up its own wall
                horizons.append(math.atan(-a * c))
                continue
            t_max = min([(half_x + x0) / c] + ([half_y / abs(s)] if s != 0 else []))
            h = math.atan(a * (c - 2 * x0 / t_max)) if t_max > x0 / c else -math.atan(a * c)
            horizons.append(max(h, 0.0))
        expected = 1 - np.mean(np.sin(horizons))
        assert svf[row, floor - steps] == pytest.approx(expected, abs=1e-4), steps
        assert svf[row, floor + steps] == pytest.approx(expected, abs=1e-4), steps
    # Open ground above the walls' top edge sees more sky than the floor.
    assert svf[row, 0] > svf[row, floor + 50] > svf[row, floor]


def test_directional_horizons_of_the_trench_floor():
    result = aperture.bake(_trench(), 2.0, horizons=8)
    assert result.horizons.shape == (301, 201, 8)
    floor = result.horizons[150, 100]
    # East and west (k = 0, 4) the walls at 30 deg; north and south (k = 2, 6) the
    # open trench, 0 deg, each to its 8-bit code's step (0.11 deg near 0, 0.43 at 30).
    assert floor[0] == pytest.approx(30.0, abs=0.25) and floor[4] == pytest.approx(30.0, abs=0.25)
    assert floor[2] == pytest.approx(0.0, abs=0.1) and floor[6] == pytest.approx(0.0, abs=0.1)
    diagonal = math.degrees(math.atan(math.tan(math.radians(30)) * math.cos(math.pi / 4)))
    assert floor[1] == pytest.approx(diagonal, abs=0.25)
    assert aperture.bake(_trench(), 2.0).horizons is None


def test_voids_are_nan_and_every_way_of_giving_them_agrees():
    z = hills(60, 70)
    voids = np.zeros(z.shape, dtype=bool)
    voids[10:20, 30:50] = True
    voids[59, 69] = True

    with_nan = z.copy()
    with_nan[voids] = np.nan
    a = aperture.bake(with_nan, 10.0)
    b = aperture.bake(np.ma.MaskedArray(z, mask=voids), 10.0)
    with_nodata = z.astype(np.float64)
    with_nodata[voids] = -32768
    c = aperture.bake(with_nodata, 10.0, nodata=-32768)
    for field in aperture.BakeResult._fields[:4]:
        va, vb, vc = getattr(a, field), getattr(b, field), getattr(c, field)
        np.testing.assert_array_equal(va, vb, err_msg=field)
        np.testing.assert_array_equal(va, vc, err_msg=field)
        nan = np.isnan(va) if va.ndim == 2 else np.isnan(va).any(axis=2)
        np.testing.assert_array_equal(nan, voids, err_msg=field)
    # The voids are filled for the geometry: the heights they took shade the rest,
    # unlike a DEM with zeros there.
    zeros = z.copy()
    zeros[voids] = 0
    assert not np.array_equal(a.sky_view_factor[~voids],
                              aperture.bake(zeros, 10.0).sky_view_factor[~voids])


def test_any_real_array_gives_the_same_bake():
    z = np.round(hills(40, 50)).astype(np.int16)
    reference = aperture.bake(z.astype(np.float32), 5.0).sky_view_factor
    for variant in (z, z.astype(np.float64), np.asfortranarray(z), z.tolist(),
                    np.ascontiguousarray(z.astype(np.float32)[:, ::-1])[:, ::-1]):
        np.testing.assert_array_equal(aperture.bake(variant, 5.0).sky_view_factor, reference)
    np.testing.assert_array_equal(aperture.bake(z, aperture.CellSize(5.0, 5.0)).sky_view_factor,
                                  reference)
    np.testing.assert_array_equal(aperture.bake(z, (5, 5)).sky_view_factor, reference)


def test_options_change_what_they_should():
    z = hills(64, 64)
    base = aperture.bake(z, 10.0)
    # Coarser cells flatten the terrain: more sky.
    assert np.mean(aperture.bake(z, (20.0, 10.0)).sky_view_factor) > np.mean(base.sky_view_factor)
    assert np.mean(aperture.bake(z, 10.0, z_scale=2.0).sky_view_factor) < np.mean(
        base.sky_view_factor)
    near = aperture.bake(z, 10.0, max_distance=30.0).sky_view_factor
    assert np.all(near >= base.sky_view_factor - 1e-6) and np.any(near > base.sky_view_factor)
    clamped = aperture.bake(z, 10.0, edge="clamp").sky_view_factor
    assert not np.array_equal(clamped, base.sky_view_factor)


def test_progress_is_reported_and_can_stop_the_bake():
    z = hills(256, 256)
    seen = []
    aperture.bake(z, 10.0, azimuths=256, progress=seen.append)
    assert seen and seen[-1] == 1.0
    assert all(0.0 <= f <= 1.0 for f in seen) and seen == sorted(seen)

    class Stop(Exception):
        pass

    def stop(fraction):
        raise Stop(fraction)

    with pytest.raises(Stop):
        aperture.bake(z, 10.0, azimuths=256, progress=stop)


def test_openness_equals_aal_bake_bit_for_bit(tmp_path, tool_env):
    from rasterio.transform import from_origin
    z = hills(50, 60)
    z[10:14, 20:25] = -9999.0  # a void block
    dem = tmp_path / "dem.tif"
    placed = rio.RasterInfo(60, 50, "EPSG:32616", from_origin(500000, 4000000, 10, 10),
                            -9999.0, None, 1.0, "float32", {})
    rio.write(dem, z, like=placed, nodata=-9999.0)
    run_tool("aal-bake", dem, "-o", tmp_path / "a.exr", "--azimuths", "16", "--max-distance",
             "200", "--openness-positive", tmp_path / "pos.tif", "--openness-negative",
             tmp_path / "neg.tif", "-q", env=tool_env)
    pos, _ = rio.read(tmp_path / "pos.tif")
    neg, _ = rio.read(tmp_path / "neg.tif")
    positive, negative = aperture.openness(z, 10.0, azimuths=16, max_distance=200,
                                           nodata=-9999.0)
    np.testing.assert_array_equal(positive, pos)
    np.testing.assert_array_equal(negative, neg)
    # NaN at the voids and on the outer ring (an open edge), values elsewhere.
    nan = np.zeros(z.shape, dtype=bool)
    nan[10:14, 20:25] = True
    nan[[0, -1], :] = nan[:, [0, -1]] = True
    np.testing.assert_array_equal(np.isnan(positive), nan)
    np.testing.assert_array_equal(np.isnan(negative), nan)
    assert np.nanmin(positive) < 90 < np.nanmax(positive)
    # Not computed unless asked; refused with curvature.
    assert aperture.bake(z, 10.0, azimuths=16).positive_openness is None
    with pytest.raises(ValueError, match="curvature"):
        aperture.openness(z, 10.0, nodata=-9999.0, curvature=True)
