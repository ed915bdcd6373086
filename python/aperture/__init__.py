"""aperture: ambient aperture lighting for terrain, from Python.

Bakes a DEM's visible sky (the sky-view factor, the visible fraction, the
bent normal and the cap's arc length), shades it as a relief and renders it
headless with Vulkan, through the same library calls as the command-line
tools aal-bake, aal-relief and aal-render, so that the results equal theirs
bit for bit (docs/python.md).

Every function takes the DEM as a 2-D array of heights in metres (row 0 is
north, column 0 west), converted once to C-contiguous float32. Voids are NaN,
the masked cells of a numpy.ma.MaskedArray, or the cells equal to
``nodata=``; they are filled with the nearest valid height for the geometry,
as the tools fill them, and are NaN in the outputs. ``cell_size`` is the
metric spacing: a number, a pair ``(dx, dy)``, or a CellSize with the
per-row spacing of a geographic grid (``aperture.rio.read`` gives it).

While a function works it holds no GIL: other Python threads run. Ctrl-C
(SIGINT) stops it within a fraction of a second and raises
KeyboardInterrupt. Bad input raises ValueError with the tools' message.
"""

from typing import NamedTuple, Optional

import numpy as np

from . import _aperture
from ._inputs import CellSize
from . import _inputs

__version__ = _aperture.__version__

__all__ = [
    "BakeResult",
    "CellSize",
    "bake",
    "metric_cell_size",
    "openness",
    "relief",
    "render",
    "sky_view_factor",
    "solar_position",
]

# aal-render's and aal-relief's defaults (tools/render/render_options.h, aal_relief.cpp).
_DEFAULT_SUN_AZIMUTH = _aperture._DEFAULT_SUN_AZIMUTH_DEG  # terrain/units.h
_DEFAULT_SUN_ELEVATION = _aperture._DEFAULT_SUN_ELEVATION_DEG
_SUN_RADIUS_DEG = _aperture._SUN_ANGULAR_RADIUS_DEG
_DEFAULT_TURBIDITY = 2.5  # kDefaultTurbidity


class BakeResult(NamedTuple):
    """What bake() returns: per texel of the DEM (H x W), NaN at voids.

    visible          float32 (H, W): the visible fraction of the sky, Omega / 2 pi, in [0, 1]
                     (aal-bake --visible).
    sky_view_factor  float32 (H, W): the GIS sky-view factor 1 - mean_phi sin(max(h(phi), 0))
                     (Zaksek et al. 2011; aal-bake --svf), in [0, 1].
    bent_normal      float32 (H, W, 3): the unit mean unoccluded direction, (x east, y north,
                     z up), the aperture cap's centre.
    arc_length       float32 (H, W): the cap's angular radius r = acos(1 - Omega / 2 pi), in
                     radians (visible = 1 - cos r).
    horizons         float32 (H, W, N) or None: with bake(horizons=N), the horizon's
                     elevation in degrees in N azimuths k * 360 / N counter-clockwise from
                     east (east, north-east, north, ... for N = 8), as aal-bake --horizons
                     stores them: 8-bit codes (steps of 0.11 deg near the horizontal, 0.43 deg
                     at 30 deg), horizons below -2 deg read as -2 deg.
    positive_openness, negative_openness
                     float32 (H, W) or None: with bake(openness=True), topographic openness
                     in degrees (Yokoyama et al. 2002; aal-bake --openness-positive and
                     --openness-negative): 90 minus the mean over the azimuths of the highest
                     signed elevation angle within max_distance, and 90 plus the mean lowest
                     one; 90 on a plane; NaN also on the outer ring with edge="open", where an
                     azimuth has no terrain ahead (docs/baking.md, "Openness").

    The bent normal and the arc length are aal-bake's aperture map (-o) before
    it is stored as 16-bit halves.
    """

    visible: np.ndarray
    sky_view_factor: np.ndarray
    bent_normal: np.ndarray
    arc_length: np.ndarray
    horizons: Optional[np.ndarray] = None
    positive_openness: Optional[np.ndarray] = None
    negative_openness: Optional[np.ndarray] = None


def bake(dem, cell_size, *, azimuths=64, max_distance=None, edge="open", curvature=False,
         refraction=0.13, horizons=0, openness=False, z_scale=1.0, nodata=None, threads=None,
         progress=None):
    """Bakes the visible sky of every texel of a DEM, as aal-bake does.

    dem           2-D array of heights (metres after z_scale), row 0 north; voids NaN,
                  masked, or equal to nodata.
    cell_size     metres between texel centres: a number, (dx, dy), or a CellSize (with
                  per-row spacing for geographic grids: aperture.rio.read gives it).
    azimuths      azimuth slices of the horizon sweep, 4 to 4096 (aal-bake --azimuths).
    max_distance  only terrain within this many metres counts; None or 0: the whole DEM.
    edge          beyond the DEM: "open" sky, or "clamp" (terrain continuing flat at the
                  edge's height).
    curvature     drop distant terrain by the Earth's curvature, with the refraction
                  coefficient `refraction` (drop = (1 - k) d^2 / 2R).
    horizons      N > 0 also keeps the horizon in N directions (4, 8, 12 or 16; azimuths a
                  multiple of N): BakeResult.horizons. 0: none.
    openness      True also computes positive and negative topographic openness
                  (BakeResult.positive_openness, .negative_openness): a second sweep, over
                  the inverted DEM, about as long again. Not with curvature.
    z_scale       metres per height unit (aal-bake --z-scale).
    nodata        texels equal to this value are voids (besides NaN and masked ones).
    threads       worker threads (None: every core), as aal-bake --threads.
    progress      callable taking the fraction done, a float in [0, 1], called in this
                  thread about every 50 ms while the bake runs, and with 1.0 at the end;
                  an exception it raises stops the bake and propagates.

    Returns a BakeResult (visible, sky_view_factor, bent_normal, arc_length, horizons,
    positive_openness, negative_openness), NaN at the DEM's voids. Equal bit for bit to
    aal-bake's --visible, --svf and openness GeoTIFFs of the same heights and spacing.

    Raises ValueError for bad input (the message aal-bake would print), KeyboardInterrupt on
    Ctrl-C (the bake stops within a block of work).
    """
    return _bake(dem, cell_size, True, azimuths=azimuths, max_distance=max_distance, edge=edge,
                 curvature=curvature, refraction=refraction, horizons=horizons,
                 openness=openness, z_scale=z_scale, nodata=nodata, threads=threads,
                 progress=progress)


def _bake(dem, cell_size, apertures, *, azimuths=64, max_distance=None, edge="open",
          curvature=False, refraction=0.13, horizons=0, openness=False, z_scale=1.0,
          nodata=None, threads=None, progress=None):
    """bake(); without `apertures` no aperture map is summed (as aal-bake without -o:
    the same rasters, sooner) and visible, bent_normal and arc_length are None."""
    handle = _inputs.make_dem(dem, cell_size, nodata, z_scale)
    if max_distance is None:
        max_distance = 0.0
    if not _inputs._is_number(max_distance):
        raise TypeError(f"max_distance must be a number of metres or None, got {max_distance!r}")
    visible, svf, bent, arc, horizon, positive, negative = _aperture._bake(
        handle, azimuths=int(_integer("azimuths", azimuths)), max_distance=float(max_distance),
        edge=str(edge), curvature=bool(curvature), refraction=float(refraction),
        horizons=int(_integer("horizons", horizons)), openness=bool(openness),
        apertures=bool(apertures), threads=_inputs.threads_value(threads),
        progress=_inputs.progress_value(progress))
    return BakeResult(visible, svf, bent, arc, horizon, positive, negative)


def sky_view_factor(dem, cell_size, **options):
    """The sky-view factor of every texel of a DEM: bake(...).sky_view_factor.

    Takes bake()'s arguments (azimuths, max_distance, edge, curvature, refraction, z_scale,
    nodata, threads, progress). Returns a float32 (H, W) array in [0, 1], NaN at voids: the
    GIS sky-view factor 1 - mean_phi sin(max(h(phi), 0)) (Zaksek et al. 2011), equal bit for
    bit to aal-bake --svf. Sums no aperture map: sooner than bake().
    """
    return _bake(dem, cell_size, False, **options).sky_view_factor


def openness(dem, cell_size, **options):
    """Topographic openness of every texel of a DEM (Yokoyama, Shirasawa & Pike 2002).

    Takes bake()'s arguments (azimuths, max_distance: the radius, None for the whole DEM;
    edge, z_scale, nodata, threads, progress; not curvature). Returns (positive, negative),
    float32 (H, W) arrays in degrees, 90 on a plane, NaN at voids and, with edge="open", on
    the outer ring: bake(..., openness=True)'s, equal bit for bit to aal-bake
    --openness-positive and --openness-negative.
    """
    result = _bake(dem, cell_size, False, openness=True, **options)
    return result.positive_openness, result.negative_openness


def relief(dem, cell_size, *, sun_azimuth=None, sun_elevation=None, time=None, lat=None,
           lon=None, sky_only=False, multidirectional=False, sky=None, mode="approx",
           sun_radius=_SUN_RADIUS_DEG, obscurance=True, obscurance_radius=None,
           obscurance_samples=16, obscurance_steps=1, water_level=None, format="byte",
           stretch=None, z_scale=1.0, nodata=None, threads=None, progress=None):
    """A top-down shaded relief of a DEM, the picture aal-relief writes (docs/relief.md).

    Lit on the CPU by the renderer's terms: the sun through the aperture (soft cast
    shadows), sky fill and near-field obscurances; the aperture map is baked first with
    aal-relief's options (64 azimuths, open edge). One pixel per texel.

    sun_azimuth, sun_elevation  degrees clockwise from north, and above the horizon
                  (default 315 and 45, as gdaldem hillshade).
    time          the sun at this UTC instant (datetime, naive = UTC, or ISO 8601 text)
                  seen from lat, lon (default: the CellSize's centre, else 45 N, 0 E).
    sky_only      the sky term alone (1 on open flat ground, darker in valleys).
    multidirectional  suns at 225, 270, 315 and 360 degrees weighted by aspect, as gdaldem
                  -multidirectional (sun_elevation sets their elevation).
    sky           the sky's share of the light k in [0, 1] (default 0.2).
    mode          "approx" (Oat's smoothstep) or "exact" cap intersection.
    sun_radius    the sun's angular radius, degrees.
    obscurance    near-field obscurances on the sky term (obscurance_radius metres, default
                  10 cells; obscurance_samples 8, 16 or 32; obscurance_steps 1 or 2).
    water_level   heights at or below this many metres are water, lit flat.
    format        "byte": uint8 1 + 254 v (0 at voids), as gdaldem hillshade; "float": the
                  value v in [0, 1] as float32, NaN at voids.
    stretch       (low, high): values from low to high fill the 8-bit range.
    z_scale, nodata, threads, progress  as for bake().

    Returns a (H, W) uint8 or float32 array, equal bit for bit to aal-relief's GeoTIFF of
    the same options.
    """
    if format not in ("byte", "float"):
        raise ValueError(f"format must be 'byte' or 'float', got {format!r}")
    sun_given = sun_azimuth is not None or sun_elevation is not None or time is not None
    if sky_only and (sun_given or multidirectional or sky is not None):
        raise ValueError("sky_only has no sun: leave out sun_azimuth, sun_elevation, time, "
                         "multidirectional and sky")
    if time is not None and (sun_azimuth is not None or sun_elevation is not None):
        raise ValueError("give time or sun_azimuth/sun_elevation, not both")
    if time is None and (lat is not None or lon is not None):
        raise ValueError("lat and lon place the sun for time; give time too")
    if multidirectional and (sun_azimuth is not None or time is not None):
        raise ValueError("multidirectional lights from 225, 270, 315 and 360 degrees: leave out "
                         "sun_azimuth and time (sun_elevation sets their elevation)")
    if stretch is not None and format == "float":
        raise ValueError("stretch is for 8-bit output: format 'float' keeps the values")
    low, high = 0.0, 1.0
    if stretch is not None:
        try:
            low, high = (float(v) for v in stretch)
        except (TypeError, ValueError):
            raise ValueError(f"stretch must be (low, high), got {stretch!r}") from None
        if not (0.0 <= low < high <= 1.0):
            raise ValueError(
                f"stretch must be (low, high) with 0 <= low < high <= 1, got {stretch!r}")
    lighting = "sky" if sky_only else ("multidirectional" if multidirectional else "sun")
    handle = _inputs.make_dem(dem, cell_size, nodata, z_scale)
    return _aperture._relief(
        handle, lighting=lighting,
        **_sun_arguments(sun_azimuth, sun_elevation, time, lat, lon, sun_radius),
        sky=_inputs.check_range("sky", sky, 0, 1), mode=str(mode), obscurance=bool(obscurance),
        **_obscurance_arguments(obscurance_radius, obscurance_samples, obscurance_steps),
        water_level=_optional_float("water_level", water_level), float_format=format == "float",
        stretch_low=low, stretch_high=high, threads=_inputs.threads_value(threads),
        progress=_inputs.progress_value(progress))


def render(dem, cell_size, *, size=(1280, 720), camera=None, look_at=None, fov=40.0,
           sun_azimuth=None, sun_elevation=None, time=None, lat=None, lon=None,
           sun_radius=_SUN_RADIUS_DEG, turbidity=_DEFAULT_TURBIDITY, ev=None, visibility=None,
           mode="approx", exaggeration=1.0, background="sky", albedo=None, obscurance=True,
           obscurance_radius=None, obscurance_samples=16, obscurance_steps=1, water_level=None,
           anisotropy=2, supersample=1, z_scale=1.0, nodata=None, device=None, threads=None,
           progress=None):
    """Renders a DEM lit by the sun and the sky, headless on Vulkan, as aal-render does.

    The aperture map is baked in memory first (aal-render's options: 64 azimuths, open edge;
    for mode "horizon" with the directional horizons of aal-bake --horizons, 16 directions).

    size          (width, height) of the image in pixels.
    camera, look_at  (x, y, z) in metres in the DEM's frame: x east, y north, z up, origin
                  at the DEM's centre (heights as given); default: framed from the
                  south-east, as aal-render.
    fov           vertical field of view, degrees (1 to 170).
    sun_azimuth, sun_elevation  degrees clockwise from north and above the horizon
                  (default 315, 45); or time (datetime, naive = UTC, or ISO 8601 text) with
                  lat, lon (default: the CellSize's centre, else 45 N, 0 E).
    sun_radius    the sun's angular radius, degrees; turbidity 2 (very clear) to 10 (hazy).
    ev            exposure value at ISO 100 (default: automatic); visibility: distance haze,
                  visibility in km (default: 20 DEM diagonals, at least 200 km).
    mode          approx, exact, horizon, baseline-lambert, baseline-ao, or a debug view
                  (debug-visible, debug-bent-normal, debug-sun, debug-sky, debug-obscurance,
                  debug-transfer).
    exaggeration  vertical exaggeration (the map is baked for the exaggerated heights).
    background    "sky", or "transparent" (alpha 0 where there is no terrain).
    albedo        a constant albedo A or (R, G, B) in [0, 1] (default: a palette by height
                  and slope).
    obscurance, obscurance_radius, obscurance_samples, obscurance_steps  the near-field
                  obscurances, as aal-render's --no-obscurance, --obscurance-*.
    water_level   paint terrain at or below this height (metres) as water.
    anisotropy    texture filtering along each pixel's footprint, 1 to 4 probes (default 2), as
                  aal-render's --anisotropy (1: one trilinear fetch, fastest, blurred in
                  oblique views).
    supersample   N x N shading points per pixel, averaged (1 to 4, default 1), as aal-render's
                  --supersample: smooth edges and no shimmer in a sequence of frames, for up
                  to N^2 the time.
    device        Vulkan device index (None: the best one).
    z_scale, nodata, threads, progress  as for bake().

    Returns the frame as a (height, width, 4) uint8 RGBA array, sRGB-encoded: the pixels of
    aal-render's PNG. Raises RuntimeError with the reason when there is no Vulkan device,
    and, with AAL_VALIDATION=1 in the environment, when the validation layer reported any
    message.
    """
    try:
        width, height = (int(v) for v in size)
    except (TypeError, ValueError):
        raise ValueError(f"size must be (width, height) in pixels, got {size!r}") from None
    if background not in ("sky", "transparent"):
        raise ValueError(f"background must be 'sky' or 'transparent', got {background!r}")
    if time is not None and (sun_azimuth is not None or sun_elevation is not None):
        raise ValueError("give time or sun_azimuth/sun_elevation, not both")
    camera = _inputs.point("camera", camera)
    look_at = _inputs.point("look_at", look_at)
    if camera is not None and look_at is not None and np.allclose(camera, look_at, rtol=0,
                                                                   atol=1e-6):
        raise ValueError("camera and look_at are the same point; the camera needs a direction")
    if albedo is not None:
        values = (albedo,) * 3 if _inputs._is_number(albedo) else tuple(albedo)
        if len(values) != 3 or not all(_inputs._is_number(v) and 0 <= v <= 1 for v in values):
            raise ValueError(f"albedo must be A or (R, G, B) with values in [0, 1], got {albedo!r}")
        albedo = tuple(float(v) for v in values)
    exaggeration = _inputs.check_range("exaggeration", exaggeration, 0.01, 100)
    handle = _inputs.make_dem(dem, cell_size, nodata, z_scale, exaggeration)
    return _aperture._render(
        handle, width=width, height=height, camera=camera, look_at=look_at,
        fov=_inputs.check_range("fov", fov, 1, 170, " degrees"),
        **_sun_arguments(sun_azimuth, sun_elevation, time, lat, lon, sun_radius),
        turbidity=_inputs.check_range("turbidity", turbidity, 2, 10),
        ev=_optional_float("ev", ev),
        visibility=_inputs.check_range("visibility", visibility, 0.1, 1e6, " km"),
        mode=str(mode), transparent=background == "transparent", albedo=albedo,
        obscurance=bool(obscurance),
        **_obscurance_arguments(obscurance_radius, obscurance_samples, obscurance_steps),
        water_level=_optional_float("water_level", water_level),
        anisotropy=_anisotropy_value(anisotropy),
        supersample=_supersample_value(supersample),
        device=-1 if device is None else int(_integer("device", device)),
        threads=_inputs.threads_value(threads), progress=_inputs.progress_value(progress))


def solar_position(when, lat, lon):
    """The sun's (azimuth, elevation) in degrees at a UTC instant, seen from lat, lon.

    when      a datetime.datetime (naive: UTC; aware: converted to UTC) or ISO 8601 text
              ("2024-06-21T12:00:00Z", offsets like "+02:00").
    lat, lon  degrees, north and east positive.

    The engine's NOAA solar position (terrain/light/solar_position.h, Meeus): azimuth
    clockwise from north in [0, 360), apparent elevation (with refraction) above the
    horizon -- what aal-render --time and aal-relief --time light with.
    """
    return _aperture._solar_position(_inputs.iso_time(when, "when"), float(lat), float(lon))


def metric_cell_size(crs, transform, width, height):
    """The CellSize the tools measure for a grid placed by a CRS and a transform.

    crs        WKT, "EPSG:n", a rasterio CRS (anything with to_wkt()), or None: the
               coordinates are metres (as the tools take a grid without a CRS).
    transform  GDAL geotransform (c, a, b, f, d, e) or an affine.Affine (rasterio's).
    width, height  the grid's size in texels.

    Geographic grids are measured on the WGS84 ellipsoid (GeographicLib), with the x spacing
    of every row; projected ones by their pixel size in metres (their ground spacing at the
    centre where the projection stretches it by over 1 %), as docs/dem-input.md describes.
    """
    wkt = "" if crs is None else (crs.to_wkt() if hasattr(crs, "to_wkt") else str(crs))
    gt = transform.to_gdal() if hasattr(transform, "to_gdal") else tuple(transform)
    if len(gt) != 6:
        raise ValueError(f"transform must be a GDAL geotransform of 6 numbers, got {transform!r}")
    s = _aperture._grid_spacing(wkt, tuple(float(v) for v in gt), int(width), int(height))
    return CellSize(s["x"], s["y"], s["rows"], None if s["center"] is None else tuple(s["center"]))


def _sun_arguments(sun_azimuth, sun_elevation, time, lat, lon, sun_radius):
    """The sun and place options relief() and render() share, checked as the tools check them."""
    return dict(
        sun_azimuth=_inputs.check_range("sun_azimuth", _default(sun_azimuth, _DEFAULT_SUN_AZIMUTH),
                                        -360, 720, " degrees"),
        sun_elevation=_inputs.check_range(
            "sun_elevation", _default(sun_elevation, _DEFAULT_SUN_ELEVATION), -90, 90, " degrees"),
        time=_inputs.iso_time(time), lat=_inputs.check_range("lat", lat, -90, 90, " degrees"),
        lon=_inputs.check_range("lon", lon, -180, 180, " degrees"),
        sun_radius=_inputs.check_range("sun_radius", sun_radius, 0.01, 20, " degrees"))


def _obscurance_arguments(radius, samples, steps):
    """The obscurance options relief() and render() share."""
    return dict(obscurance_radius=_optional_float("obscurance_radius", radius),
                obscurance_samples=int(_integer("obscurance_samples", samples)),
                obscurance_steps=int(_integer("obscurance_steps", steps)))


def _default(value, default):
    return default if value is None else value


def _integer(name, value):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer, got {value!r}")
    if not -2**31 <= value < 2**31:
        raise ValueError(f"{name} is out of range, got {value}")
    return value


def _supersample_value(value):
    value = _integer("supersample", value)
    if not 1 <= value <= 4:
        raise ValueError(f"supersample must be 1 to 4 points per pixel and axis, got {value}")
    return int(value)


def _anisotropy_value(value):
    value = _integer("anisotropy", value)
    if not 1 <= value <= 4:
        raise ValueError(f"anisotropy must be 1 to 4 probes, got {value}")
    return int(value)


def _optional_float(name, value):
    if value is None:
        return None
    if not _inputs._is_number(value):
        raise TypeError(f"{name} must be a number, got {value!r}")
    return float(value)
