"""Reading DEMs and writing results as GIS rasters, with rasterio.

``read`` gives the heights and the cell size the tools would use for a file;
``write`` writes an array placed like the DEM it came from (CRS, transform,
nodata). rasterio is imported on first use: aperture itself needs only NumPy.
"""

import errno
import math
import os
from typing import Any, NamedTuple, Optional

import numpy as np

from ._inputs import CellSize
from . import _aperture


def _rasterio():
    try:
        import rasterio
    except ImportError as e:
        raise ImportError(
            "aperture.rio needs rasterio (Debian: apt-get install python3-rasterio; "
            "elsewhere: pip install rasterio)") from e
    return rasterio


class RasterInfo(NamedTuple):
    """Where a raster lies and what aperture makes of it (aperture.rio.read).

    width, height  size in texels.
    crs            rasterio CRS, or None.
    transform      affine.Affine of the array as read (row 0 north: a south-up file's
                   rows are flipped, and its transform with them).
    nodata         the file's nodata value, or None.
    cell_size      the CellSize the tools measure (per-row x spacing for geographic
                   grids, the centre where known), or None when the file is not
                   georeferenced (then give bake() a cell size yourself).
    z_scale        metres per height unit: a vertical CRS's unit (0.3048 for feet), else 1.
    dtype          the band's type as stored.
    profile        the file's rasterio profile.
    """

    width: int
    height: int
    crs: Any
    transform: Any
    nodata: Optional[float]
    cell_size: Optional[CellSize]
    z_scale: float
    dtype: str
    profile: dict


def read(path, band=1, masked=False):
    """Reads one band of a raster (any format GDAL opens) as the tools read a DEM.

    Returns (heights, info): the heights as float32 (H, W), row 0 north, the band's scale
    and offset applied, with NaN at voids (nodata, the mask or alpha band, non-finite
    samples) -- or, with masked=True, a numpy masked array of them; and a RasterInfo whose
    cell_size and z_scale, handed to aperture.bake(), give the tools' results for the file:

        dem, info = aperture.rio.read("dem.tif")
        result = aperture.bake(dem, info.cell_size, z_scale=info.z_scale)
    """
    rasterio = _rasterio()
    import warnings
    with warnings.catch_warnings():
        # A file without georeferencing: info.cell_size is None, said below.
        warnings.simplefilter("ignore", rasterio.errors.NotGeoreferencedWarning)
        with rasterio.open(os.fspath(path)) as ds:
            data = ds.read(band, masked=True)
            scale, offset = ds.scales[band - 1], ds.offsets[band - 1]
            transform, crs, nodata = ds.transform, ds.crs, ds.nodata
            width, height = ds.width, ds.height
            dtype = ds.dtypes[band - 1]
            profile = dict(ds.profile)
            georeferenced = crs is not None or not transform.is_identity
    mask = np.ma.getmaskarray(data)
    values = np.asarray(data.data, dtype=np.float64 if (scale, offset) != (1.0, 0.0) else None)
    if (scale, offset) != (1.0, 0.0):
        values = values * scale + offset
    with np.errstate(over="ignore", invalid="ignore"):
        heights = values.astype(np.float32)
    mask = mask | ~np.isfinite(heights)

    cell_size, z_scale = None, 1.0
    if georeferenced:
        wkt = crs.to_wkt() if crs is not None else ""
        s = _aperture._grid_spacing(wkt, tuple(transform.to_gdal()), width, height)
        center = None if s["center"] is None else tuple(s["center"])
        cell_size = CellSize(s["x"], s["y"], s["rows"], center)
        if s["z_unit"] is not None:
            z_scale = s["z_unit"]
    if georeferenced and transform.e > 0:  # south-up: row 0 made north, as the tools read it
        heights, mask = heights[::-1].copy(), mask[::-1].copy()
        transform = transform.__class__(transform.a, transform.b, transform.c, transform.d,
                                        -transform.e, transform.f + height * transform.e)
    info = RasterInfo(width, height, crs, transform, nodata, cell_size, z_scale, dtype, profile)
    if masked:
        return np.ma.MaskedArray(heights, mask=mask), info
    heights[mask] = np.nan
    return heights, info


_DRIVERS = {".tif": "GTiff", ".tiff": "GTiff", ".png": "PNG", ".jpg": "JPEG", ".jpeg": "JPEG"}
# Image formats: pixels only (no georeferencing beside them in .aux.xml files).
_IMAGE_DRIVERS = ("PNG", "JPEG")


def write(path, array, like=None, *, nodata=None, crs=None, transform=None, driver=None):
    """Writes an array as a raster placed like `like` (a RasterInfo from read()).

    array      (H, W) or (H, W, bands), any type rasterio writes (float32 results, uint8
               reliefs and renders); masked cells and, in float arrays, NaN are voids.
    like       a RasterInfo: its CRS and transform place the array (which must have its
               width and height) and its nodata value marks the voids (the DEM's nodata
               value when the array's type holds it, else NaN for float arrays; give
               nodata=float("nan") for NaN, as aal-bake's float GeoTIFFs have).
    nodata     the value voids get (overrides like's); crs and transform override like's.
    driver     GDAL driver; default by extension: .tif GTiff, .png PNG, .jpg JPEG. PNG and
               JPEG files get the pixels only.
    """
    rasterio = _rasterio()
    path = os.fspath(path)
    if driver is None:
        driver = _DRIVERS.get(os.path.splitext(path)[1].lower())
        if driver is None:
            raise ValueError(f"{path}: give driver= (no driver known for its extension)")
    mask = np.ma.getmaskarray(array) if isinstance(array, np.ma.MaskedArray) else None
    data = np.asarray(array.data if isinstance(array, np.ma.MaskedArray) else array)
    if data.ndim == 2:
        data = data[np.newaxis]
        if mask is not None:
            mask = mask[np.newaxis]
    elif data.ndim == 3:
        data = np.moveaxis(data, 2, 0)  # bands first, as GDAL stores them
        if mask is not None:
            mask = np.moveaxis(mask, 2, 0)
    else:
        raise ValueError(f"array must be (H, W) or (H, W, bands), got shape {data.shape}")
    bands, height, width = data.shape
    if like is not None and (like.width, like.height) != (width, height):
        raise ValueError(f"array is {width} x {height}, like is {like.width} x {like.height}")
    if crs is None and like is not None:
        crs = like.crs
    if transform is None and like is not None:
        transform = like.transform

    floating = np.issubdtype(data.dtype, np.floating)
    voids = mask if mask is not None else np.zeros(data.shape, dtype=bool)
    if floating:
        voids = voids | np.isnan(data)
    if nodata is None and like is not None and like.nodata is not None:
        if _holds(data.dtype, like.nodata):
            nodata = like.nodata
        elif floating:
            nodata = math.nan
    if nodata is None and voids.any():
        if not floating:
            raise ValueError(f"{path}: the array has voids; give nodata= (a {data.dtype} value)")
        nodata = math.nan
    if voids.any():
        data = data.copy()
        data[voids] = nodata

    profile = {"driver": driver, "width": width, "height": height, "count": bands,
               "dtype": data.dtype}
    if driver in _IMAGE_DRIVERS:
        if data.dtype != np.uint8 and not (driver == "PNG" and data.dtype == np.uint16):
            raise ValueError(f"{path}: {driver} holds 8-bit pixels, got {data.dtype}")
    else:
        profile.update(crs=crs, transform=transform, nodata=nodata)
        if driver == "GTiff":
            profile.update(compress="deflate", tiled=width >= 256 and height >= 256)
    # Written to a temporary file beside it and renamed into place, as the tools write,
    # so that an interrupted write never leaves a broken file under the name.
    import tempfile
    import warnings
    folder = os.path.dirname(os.path.abspath(path))
    name, extension = os.path.splitext(os.path.basename(path))
    handle, temporary = tempfile.mkstemp(prefix=f".{name}.tmp-", suffix=extension, dir=folder)
    os.close(handle)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", rasterio.errors.NotGeoreferencedWarning)
            with rasterio.open(temporary, "w", **profile) as out:
                out.write(data)
                if driver == "GTiff":
                    out.update_tags(TIFFTAG_SOFTWARE=_aperture.software)  # what wrote it
        _flush(temporary)
        os.replace(temporary, path)
        _flush(folder, directory=True)
    except BaseException:
        for leftover in (temporary, temporary + ".aux.xml"):
            if os.path.exists(leftover):
                os.remove(leftover)
        raise


def _flush(path, directory=False):
    """fsync a file or folder, so that a renamed output survives a power loss as the
    tools' outputs do (docs/dem-input.md, "Outputs")."""
    handle = os.open(path, os.O_RDONLY | (os.O_DIRECTORY if directory else 0))
    try:
        os.fsync(handle)
    except OSError as error:
        if not (directory and error.errno in (errno.EINVAL, errno.EROFS)):
            raise
    finally:
        os.close(handle)


def _holds(dtype, value):
    """Whether an array of `dtype` holds `value` as nodata: float types any value finite as
    float32 (aal-bake's rule, preprocess/sky_view_factor_tiles.h), integer types exactly."""
    if np.issubdtype(dtype, np.floating):
        with np.errstate(over="ignore"):
            return bool(np.isfinite(np.float32(value)))
    if np.issubdtype(dtype, np.integer):
        info = np.iinfo(dtype)
        return not math.isnan(value) and float(value).is_integer() and info.min <= value <= info.max
    return False
