"""aperture.render: headless Vulkan frames (lavapipe) under the validation layer.

The validation layer is on for every render here (AAL_VALIDATION=1, set by CTest and
below): render() raises RuntimeError on any validation message, and the layer's
messages on stderr fail the tests too.
"""

import os
import subprocess
import sys

import numpy as np
import pytest

import aperture
from aperture import rio

from conftest import hills, run_tool

# Read by the engine when it makes its Vulkan instance, i.e. at every render.
os.environ["AAL_VALIDATION"] = "1"


@pytest.fixture(autouse=True)
def no_validation_messages(capfd):
    yield
    assert "vulkan validation" not in capfd.readouterr().err


def test_a_small_render_has_terrain_and_sky():
    image = aperture.render(hills(48, 64), 20.0, size=(96, 64))
    assert image.shape == (64, 96, 4) and image.dtype == np.uint8
    rgb = image[..., :3].astype(np.float64)
    assert np.all(image[..., 3] == 255)
    assert rgb.std() > 10 and np.unique(image.reshape(-1, 4), axis=0).shape[0] > 200
    # The default camera looks down from the south-east: terrain fills the middle, and
    # the top row is sky (bluer than it is red).
    assert rgb[0, :, 2].mean() > rgb[0, :, 0].mean()


def test_transparent_background_and_modes():
    z = hills(48, 64)
    clear = aperture.render(z, 20.0, size=(96, 64), background="transparent",
                            camera=(0, -3000, 1500), look_at=(0, 0, 300))
    alpha = clear[..., 3]
    assert (alpha == 0).any() and (alpha == 255).any()
    shaded = aperture.render(z, 20.0, size=(96, 64), camera=(0, -3000, 1500),
                             look_at=(0, 0, 300), mode="horizon", sun_elevation=10)
    lambert = aperture.render(z, 20.0, size=(96, 64), camera=(0, -3000, 1500),
                              look_at=(0, 0, 300), mode="baseline-lambert", sun_elevation=10)
    assert not np.array_equal(shaded, lambert)


def test_equals_aal_render_bit_for_bit(tmp_path, tool_env):
    z = hills(40, 56)
    from rasterio.transform import from_origin
    placed = rio.RasterInfo(56, 40, "EPSG:32616", from_origin(500000, 4000000, 25, 25), None,
                            None, 1.0, "float32", {})
    rio.write(tmp_path / "dem.tif", z, like=placed)
    tool_env["AAL_VALIDATION"] = "1"
    import rasterio
    import warnings

    def tool_frame(name, *options, sun=(200, 20)):
        run_tool("aal-render", tmp_path / "dem.tif", "-o", tmp_path / name, "--size", "96x64",
                 "--sun-azimuth", str(sun[0]), "--sun-elevation", str(sun[1]), "--exaggeration",
                 "2", *options, "-q", env=tool_env)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", rasterio.errors.NotGeoreferencedWarning)
            with rasterio.open(tmp_path / name) as png:
                return np.moveaxis(png.read(), 0, 2)

    dem, info = rio.read(tmp_path / "dem.tif")

    def module_frame(**options):
        return aperture.render(dem, info.cell_size, size=(96, 64), sun_azimuth=200,
                               sun_elevation=20, exaggeration=2, **options)

    image = module_frame()
    np.testing.assert_array_equal(image, tool_frame("frame.png"))
    # --anisotropy and anisotropy= are one setting: one trilinear fetch blurs the oblique
    # view into another picture, the same in both.
    one = module_frame(anisotropy=1)
    np.testing.assert_array_equal(one, tool_frame("one.png", "--anisotropy", "1"))
    assert not np.array_equal(one, image)
    # --supersample and supersample= too: 2 x 2 points per pixel, the same pixels as the tool's.
    four = module_frame(supersample=2)
    assert four.shape == image.shape
    np.testing.assert_array_equal(four, tool_frame("four.png", "--supersample", "2"))
    assert not np.array_equal(four, image)
    # mode="horizon" bakes the horizons aal-bake --horizons writes by default (16
    # directions of 8 bits): the picture of aal-render with that file, not of 8 directions.
    for directions in (16, 8):
        run_tool("aal-bake", tmp_path / "dem.tif", "-o", tmp_path / f"h{directions}.exr",
                 "--z-scale", "2", "--horizons", tmp_path / f"h{directions}.horizons",
                 "--horizon-directions", str(directions), "-q", env=tool_env)
    low = dict(sun_azimuth=250, sun_elevation=6, mode="horizon")
    horizon = aperture.render(dem, info.cell_size, size=(96, 64), exaggeration=2, **low)

    def horizon_tool(directions):
        return tool_frame(f"h{directions}.png", "--mode", "horizon", "--horizons",
                          tmp_path / f"h{directions}.horizons", sun=(250, 6))
    np.testing.assert_array_equal(horizon, horizon_tool(16))
    assert not np.array_equal(horizon, horizon_tool(8))


def test_no_vulkan_device_is_a_runtime_error():
    # A child process whose Vulkan loader finds no driver.
    code = ("import numpy, aperture\n"
            "try:\n"
            "    aperture.render(numpy.zeros((8, 8)), 1.0, size=(16, 16))\n"
            "except RuntimeError as e:\n"
            "    print('RuntimeError:', e)\n")
    env = dict(os.environ, VK_ICD_FILENAMES="/nonexistent/icd.json", AAL_VALIDATION="0")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            env=env, timeout=60)
    assert result.returncode == 0, result.stderr
    assert "RuntimeError: no Vulkan 1.3 driver found" in result.stdout
