"""Argument checks and conversions shared by aperture's functions.

Every DEM goes through ``dem_and_spacing`` once: the samples become one
C-contiguous float32 array (the type the tools load every DEM as), the voids
one flag per texel, the cell size the spacing the library takes.
"""

import datetime as _datetime
import math
import numbers
from typing import NamedTuple, Optional, Tuple

import numpy as np

from . import _aperture


class CellSize(NamedTuple):
    """The metric spacing of a DEM's texel centres, in metres.

    ``x`` is the east-west spacing (at the centre row), ``y`` the north-south
    one. ``rows``, when given, holds the east-west spacing of every row, north
    to south: a geographic (latitude/longitude) grid's cells narrow towards
    the pole, and the tools bake such a DEM with the spacing of each row.
    ``center`` is the DEM's centre as WGS84 (latitude, longitude) in degrees,
    where the sun is placed for ``time=`` when no ``lat``/``lon`` is given.

    ``aperture.rio.read`` and ``aperture.metric_cell_size`` return the
    CellSize the tools measure for a georeferenced grid. A plain number
    ``d`` stands for ``CellSize(d, d)`` and a pair ``(dx, dy)`` for
    ``CellSize(dx, dy)``.
    """

    x: float
    y: float
    rows: Optional[np.ndarray] = None
    center: Optional[Tuple[float, float]] = None


def _is_number(value):
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def cell_spacing(cell_size, height):
    """(x, y, rows or None, center or None) of a cell_size argument."""
    if isinstance(cell_size, CellSize):
        rows = cell_size.rows
        if rows is not None:
            rows = np.ascontiguousarray(rows, dtype=np.float64)
            if rows.ndim != 1 or rows.shape[0] != height:
                raise ValueError(
                    f"cell_size: the x spacing per row must be {height} values (one per row), "
                    f"got shape {rows.shape}")
        center = None
        if cell_size.center is not None:
            center = (float(cell_size.center[0]), float(cell_size.center[1]))
        return float(cell_size.x), float(cell_size.y), rows, center
    if _is_number(cell_size):
        return float(cell_size), float(cell_size), None, None
    if (isinstance(cell_size, (tuple, list, np.ndarray)) and len(cell_size) == 2
            and all(_is_number(v) for v in cell_size)):
        return float(cell_size[0]), float(cell_size[1]), None, None
    raise TypeError(
        "cell_size must be a number of metres, a pair (dx, dy) of them, or an "
        f"aperture.CellSize (as aperture.rio.read returns), got {cell_size!r}")


def dem_samples(dem, nodata=None):
    """(heights as C-contiguous float32, void flags as uint8 or None)."""
    mask = None
    if isinstance(dem, np.ma.MaskedArray):
        mask = np.ma.getmaskarray(dem)
        dem = dem.data
    a = np.asarray(dem)
    if a.ndim != 2:
        raise ValueError(
            f"dem must be a 2-D array (rows x columns, row 0 north), got shape {a.shape}")
    if a.size == 0:
        raise ValueError(f"dem is empty: shape {a.shape}")
    if a.dtype.kind not in "fiu":
        raise ValueError(f"dem must hold real numbers, got dtype {a.dtype}")
    voids = mask
    if nodata is not None:
        if not _is_number(nodata):
            raise TypeError(f"nodata must be a number, got {nodata!r}")
        if not math.isnan(nodata):  # NaN is a void anyway
            equal = a == nodata
            voids = equal if voids is None else (voids | equal)
    # One conversion, rounding as the DEM reader does (float64 -> float32,
    # beyond float range: infinite, so a void).
    with np.errstate(over="ignore", invalid="ignore"):
        z = np.ascontiguousarray(a, dtype=np.float32)
    if voids is not None:
        voids = np.ascontiguousarray(voids, dtype=np.uint8)
    return z, voids


def make_dem(dem, cell_size, nodata, z_scale, exaggeration=1.0):
    """The _Dem one call of the compiled module consumes."""
    z, voids = dem_samples(dem, nodata)
    x, y, rows, center = cell_spacing(cell_size, z.shape[0])
    if not _is_number(z_scale):
        raise TypeError(f"z_scale must be a number, got {z_scale!r}")
    return _aperture._Dem(z, voids, x, y, rows, center, float(z_scale), float(exaggeration))


def threads_value(threads):
    if threads is None:
        return 0
    if not isinstance(threads, numbers.Integral) or isinstance(threads, bool) or threads < 1:
        raise ValueError(
            f"threads must be a positive integer or None (every core), got {threads!r}")
    return int(threads)


def progress_value(progress):
    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be a callable taking a float in [0, 1], got {progress!r}")
    return progress


def iso_time(when, name="time"):
    """ISO 8601 text of a datetime (naive: UTC) or of text, for the library's parser."""
    if when is None:
        return None
    if isinstance(when, _datetime.datetime):
        if when.tzinfo is not None:
            when = when.astimezone(_datetime.timezone.utc).replace(tzinfo=None)
        return when.isoformat()
    if isinstance(when, _datetime.date):
        return _datetime.datetime(when.year, when.month, when.day).isoformat()
    if isinstance(when, str):
        return when
    raise TypeError(f"{name} must be a datetime.datetime or ISO 8601 text, got {when!r}")


def check_range(name, value, low, high, unit=""):
    """The tools' option ranges (CLI11 checks) for the same arguments."""
    if value is None:
        return None
    if not _is_number(value):
        raise TypeError(f"{name} must be a number, got {value!r}")
    value = float(value)
    if not (low <= value <= high):
        raise ValueError(f"{name} must be in [{low:g}, {high:g}]{unit}, got {value:g}")
    return value


def point(name, value):
    if value is None:
        return None
    values = tuple(value)
    if len(values) != 3 or not all(_is_number(v) and math.isfinite(v) for v in values):
        raise ValueError(f"{name} must be (x, y, z) in metres, finite, got {value!r}")
    return tuple(float(v) for v in values)
