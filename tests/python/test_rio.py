"""aperture.rio: GIS rasters in and out, placed like the DEM."""

import sys

import numpy as np
import pytest

import aperture
from aperture import rio

from conftest import JACKSBORO


def test_a_round_trip_keeps_crs_transform_nodata_and_values(tmp_path, jacksboro):
    dem, info = jacksboro
    result = aperture.bake(dem, info.cell_size)
    svf = result.sky_view_factor.copy()
    svf[:3, :5] = np.nan  # voids
    rio.write(tmp_path / "svf.tif", svf, like=info)

    back, back_info = rio.read(tmp_path / "svf.tif")
    assert back_info.crs == info.crs and back_info.crs.to_epsg() == 4326
    assert back_info.transform == info.transform
    # The DEM's nodata value (-32768), which float32 holds, as aal-bake writes voids.
    assert back_info.nodata == info.nodata == -32768
    np.testing.assert_array_equal(back, svf)  # NaN where the voids are
    masked, _ = rio.read(tmp_path / "svf.tif", masked=True)
    assert masked.mask.sum() == 15
    # And the georeferencing gives the same cell size again.
    assert back_info.cell_size.x == info.cell_size.x
    np.testing.assert_array_equal(back_info.cell_size.rows, info.cell_size.rows)
    # The file says what wrote it, as the tools' GeoTIFFs do, and the write went through a
    # temporary renamed into place: nothing else is left in the folder.
    import rasterio
    with rasterio.open(tmp_path / "svf.tif") as written:
        assert written.tags()["TIFFTAG_SOFTWARE"] == aperture._aperture.software
    assert sorted(p.name for p in tmp_path.iterdir()) == ["svf.tif"]


def test_the_dem_reads_as_the_tools_read_it(jacksboro):
    dem, info = jacksboro
    assert dem.dtype == np.float32 and dem.shape == (344, 403) == (info.height, info.width)
    assert info.dtype == "int16" and info.z_scale == 1.0
    assert np.nanmin(dem) == 236 and np.nanmax(dem) == 1076  # aal-info's height range
    assert not np.isnan(dem).any()


def test_projected_grids_south_up_files_and_nodata(tmp_path):
    from rasterio.transform import Affine
    z = np.arange(12 * 10, dtype=np.float32).reshape(12, 10)
    z[2, 3] = -1
    south_up = Affine(25.0, 0, 300000, 0, 25.0, 5000000)  # row 0 is the southern edge
    placed = rio.RasterInfo(10, 12, "EPSG:32633", south_up, -1.0, None, 1.0, "float32", {})
    rio.write(tmp_path / "dem.tif", z, like=placed)
    dem, info = rio.read(tmp_path / "dem.tif")
    # Flipped to row 0 north, as the tools read it, with a north-up transform.
    np.testing.assert_array_equal(dem[::-1][~np.isnan(dem[::-1])], z[z != -1])
    assert np.isnan(dem[12 - 1 - 2, 3])
    assert info.transform.e < 0 and info.transform * (0, 0) == (300000, 5000000 + 12 * 25)
    assert info.cell_size.x == info.cell_size.y == 25.0 and info.cell_size.rows is None
    assert info.cell_size.center is not None  # UTM places it on the Earth
    # Written back north-up, it reads the same.
    rio.write(tmp_path / "north.tif", dem, like=info)
    again, again_info = rio.read(tmp_path / "north.tif")
    np.testing.assert_array_equal(again, dem)
    assert again_info.transform == info.transform


def test_images_and_files_without_georeferencing(tmp_path):
    grey = (np.arange(64 * 48) % 251).astype(np.uint8).reshape(48, 64)
    rgb = np.stack([grey, grey[::-1], 255 - grey], axis=2)
    rio.write(tmp_path / "grey.png", grey)
    rio.write(tmp_path / "rgb.png", rgb)
    back, info = rio.read(tmp_path / "grey.png")
    np.testing.assert_array_equal(back, grey)
    assert info.cell_size is None  # not georeferenced: bake() needs a cell size given
    import warnings
    import rasterio
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rasterio.errors.NotGeoreferencedWarning)
        with rasterio.open(tmp_path / "rgb.png") as png:
            np.testing.assert_array_equal(np.moveaxis(png.read(), 0, 2), rgb)
    assert not (tmp_path / "grey.png.aux.xml").exists()
    with pytest.raises(ValueError, match="8-bit"):
        rio.write(tmp_path / "bad.png", grey.astype(np.float32))
    with pytest.raises(ValueError, match="give nodata="):
        rio.write(tmp_path / "bad.tif", np.ma.MaskedArray(grey, mask=grey == 0))


def test_metric_cell_size_equals_rio_read(jacksboro):
    _, info = jacksboro
    size = aperture.metric_cell_size(info.crs, info.transform, info.width, info.height)
    assert size.x == info.cell_size.x and size.y == info.cell_size.y
    np.testing.assert_array_equal(size.rows, info.cell_size.rows)
    # Without a CRS the coordinates are metres, as the tools take them.
    plain = aperture.metric_cell_size(None, (0, 2.5, 0, 100, 0, -4.0), 10, 10)
    assert (plain.x, plain.y, plain.rows) == (2.5, 4.0, None)


def test_a_missing_rasterio_says_what_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "rasterio", None)  # import rasterio fails
    with pytest.raises(ImportError, match="aperture.rio needs rasterio"):
        rio.read(JACKSBORO)


def test_a_write_is_flushed_before_its_rename_and_its_folder_after(tmp_path, monkeypatch):
    import os
    calls = []
    real_fsync, real_replace = os.fsync, os.replace

    def fsync(handle):
        calls.append(("fsync", os.readlink(f"/proc/self/fd/{handle}")))
        return real_fsync(handle)

    def replace(source, target):
        calls.append(("replace", os.fspath(target)))
        return real_replace(source, target)

    monkeypatch.setattr(os, "fsync", fsync)
    monkeypatch.setattr(os, "replace", replace)
    target = tmp_path / "grey.tif"
    rio.write(target, np.zeros((8, 8), np.float32))
    kinds = [kind for kind, _ in calls]
    assert kinds == ["fsync", "replace", "fsync"], calls
    assert os.path.basename(calls[0][1]).startswith(".grey.tmp-")  # the temporary
    assert calls[1][1] == str(target)
    assert calls[2][1] == os.path.realpath(tmp_path)
