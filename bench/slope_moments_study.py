#!/usr/bin/env python3
"""How well a mip level's slopes give the mean sun shading of the DEM texels it covers.

A pixel that covers a block of b x b DEM texels sees the mean of their outgoing
radiance, each facet weighted by the area it shows the camera. Per unit of plan
area a facet of slope s (dz/dx, dz/dy) shows V_z - s . V_xy (its normal times its
surface area), so the block's sun term is

    T = sum(max(0, N(s) . L) w(s)) / sum(w(s)),   w(s) = max(0, V_z - s . V_xy),

with N(s) = normalize(-s_x, -s_y, 1). This study compares estimators of T from
what a level could store (docs/comparison.md, "Second moments of the slopes"):

  level CD     the central differences of the level's own heights (box means of
               the DEM's), two of its texels apart
  mean slope   the block's mean slope (what the slope texture's levels hold)
  cov          the mean and the covariance of the slopes: N . L averaged over
               four points that match both (mean +- sqrt(2 lambda) e along the
               covariance's principal axes), unweighted
  cov + w      the same points weighted by w: the footprint's visible slopes
  iso + w      the same with the covariance's trace alone (a Toksvig-like scalar)
  diag + w     the same with its diagonal alone (no cross moment)

The covariance comes from the block's first and second moments, which filter
linearly (Olano and Baker, "LEAN Mapping", 2010). Prints the relative RMSE
(RMS of estimate - T over the blocks, over the mean of T) in percent, per block
size and sun. Needs numpy and rasterio.

    bench/slope_moments_study.py heightmaps/jacksboro_fault_dem.tif fbm512.tif
"""
import argparse
import math

import numpy as np
import rasterio


def direction(azimuth_deg, elevation_deg):
    az, el = math.radians(azimuth_deg), math.radians(elevation_deg)
    return np.array([math.sin(az) * math.cos(el), math.cos(az) * math.cos(el), math.sin(el)])


def load(path):
    """Heights (rows north to south) and the cell size in metres (x, y)."""
    with rasterio.open(path) as dem:
        z = dem.read(1).astype(np.float64)
        t = dem.transform
        cx, cy = abs(t.a), abs(t.e)
        if dem.crs is not None and dem.crs.is_geographic:
            lat = math.radians(t.f + t.e * dem.height / 2)
            cx *= 111320.0 * math.cos(lat)
            cy *= 110574.0
    return z, cx, cy


def slopes(z, cx, cy):
    """Central differences one texel apart (one-sided at the edge), east and north."""
    gy, gx = np.gradient(z, cy, cx)
    return gx, -gy


def lambert(sx, sy, sun):
    return np.maximum(0.0, (sun[2] - sx * sun[0] - sy * sun[1]) / np.sqrt(1 + sx * sx + sy * sy))


def shown_area(sx, sy, view):
    return np.maximum(0.0, view[2] - sx * view[0] - sy * view[1])


def block_mean(a, b):
    h, w = a.shape[0] // b * b, a.shape[1] // b * b
    return a[:h, :w].reshape(h // b, b, w // b, b).mean(axis=(1, 3))


def four_points(mx, my, cxx, cyy, cxy, sun, view, weighted):
    """N . L over four equally weighted points with the given mean and covariance."""
    half_trace = (cxx + cyy) / 2
    spread = np.sqrt(np.maximum(0.0, half_trace ** 2 - (cxx * cyy - cxy * cxy)))
    angle = 0.5 * np.arctan2(2 * cxy, cxx - cyy)
    axes = ((np.cos(angle), np.sin(angle), np.maximum(0.0, half_trace + spread)),
            (-np.sin(angle), np.cos(angle), np.maximum(0.0, half_trace - spread)))
    total = weights = 0.0
    for ex, ey, variance in axes:
        for sign in (1.0, -1.0):
            a = sign * np.sqrt(2 * variance)
            px, py = mx + a * ex, my + a * ey
            w = shown_area(px, py, view) if weighted else 1.0
            total = total + lambert(px, py, sun) * w
            weights = weights + w
    return total / np.maximum(weights, 1e-12)


ESTIMATORS = ("level CD", "mean slope", "cov", "cov + w", "iso + w", "diag + w")


def study(path, suns, view, blocks):
    z, cx, cy = load(path)
    sx, sy = slopes(z, cx, cy)
    w = shown_area(sx, sy, view)
    for b in blocks:
        mx, my = block_mean(sx, b), block_mean(sy, b)
        cxx = block_mean(sx * sx, b) - mx * mx
        cyy = block_mean(sy * sy, b) - my * my
        cxy = block_mean(sx * sy, b) - mx * my
        iso = (cxx + cyy) / 2
        lx, ly = slopes(block_mean(z, b), cx * b, cy * b)
        for sun_elevation, sun in suns:
            truth = block_mean(lambert(sx, sy, sun) * w, b) / np.maximum(block_mean(w, b), 1e-12)
            estimates = (
                lambert(lx, ly, sun),
                lambert(mx, my, sun),
                four_points(mx, my, cxx, cyy, cxy, sun, view, False),
                four_points(mx, my, cxx, cyy, cxy, sun, view, True),
                four_points(mx, my, iso, iso, 0 * iso, sun, view, True),
                four_points(mx, my, cxx, cyy, 0 * cxy, sun, view, True),
            )
            errors = [np.sqrt(np.mean((e - truth) ** 2)) / np.mean(truth) * 100 for e in estimates]
            print(f"| {path.split('/')[-1]} | {b} | {sun_elevation:g}° | "
                  + " | ".join(f"{e:.2f}" for e in errors) + " |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dems", nargs="+", help="GDAL-readable DEMs")
    parser.add_argument("--sun-azimuth", type=float, default=250)
    parser.add_argument("--sun-elevations", default="45,20,8")
    parser.add_argument("--view-azimuth", type=float, default=70,
                        help="azimuth of the direction from the ground to the camera")
    parser.add_argument("--view-elevation", type=float, default=30)
    parser.add_argument("--blocks", default="2,4,8")
    args = parser.parse_args()
    suns = [(float(e), direction(args.sun_azimuth, float(e)))
            for e in args.sun_elevations.split(",")]
    view = direction(args.view_azimuth, args.view_elevation)
    print("| DEM | block | sun elevation | " + " | ".join(ESTIMATORS) + " |")
    print("|---" * (3 + len(ESTIMATORS)) + "|")
    for path in args.dems:
        study(path, suns, view, [int(b) for b in args.blocks.split(",")])


if __name__ == "__main__":
    main()
