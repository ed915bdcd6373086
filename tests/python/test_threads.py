"""The GIL is released while a bake runs, and Ctrl-C stops it within a second.

Both need a bake of seconds: a 1024 x 1024 DEM, whose sweep costs 20-30 ms per azimuth
on two cores (a 16-azimuth bake is timed first to size the others).
"""

import os
import signal
import threading
import time

import numpy as np
import pytest

import aperture


@pytest.fixture(scope="module")
def big_dem():
    rng = np.random.default_rng(3)
    return (rng.random((1024, 1024)) * 50).astype(np.float32)


def _seconds_per_azimuth(dem):
    start = time.perf_counter()
    aperture.bake(dem, 10.0, azimuths=16)
    return (time.perf_counter() - start) / 16


def test_other_threads_run_while_a_bake_runs(big_dem):
    # About 1.5 s of bake (at least 8 azimuths).
    azimuths = int(np.clip(1.5 / _seconds_per_azimuth(big_dem), 8, 4096)) // 4 * 4
    state = {"count": 0, "max_gap": 0.0, "baking": False}
    stop = threading.Event()

    def busy():
        last = time.perf_counter()
        while not stop.is_set():
            now = time.perf_counter()
            if state["baking"]:
                state["count"] += 1
                state["max_gap"] = max(state["max_gap"], now - last)
            last = now

    thread = threading.Thread(target=busy)
    thread.start()
    try:
        time.sleep(0.05)
        state["baking"] = True
        start = time.perf_counter()
        aperture.bake(big_dem, 10.0, azimuths=azimuths)
        seconds = time.perf_counter() - start
        state["baking"] = False
    finally:
        stop.set()
        thread.join()
    # With the GIL held through the bake the busy thread would stand still for all of
    # it: one gap as long as the bake, and hardly any iterations. (The bounds leave room
    # for a loaded machine, where the scheduler alone can pause the thread for 0.1-0.3 s.)
    assert seconds > 0.5, f"the bake took {seconds:.2f} s, too short to tell"
    assert state["max_gap"] < seconds / 3, (state, seconds)
    assert state["count"] > 1000, (state, seconds)


def test_ctrl_c_stops_a_bake_within_a_second(big_dem):
    assert threading.current_thread() is threading.main_thread()  # where signals go
    # About 10 s of bake (tens on two cores), interrupted after 0.5 s.
    per_azimuth = _seconds_per_azimuth(big_dem)
    azimuths = int(np.clip(10.0 / per_azimuth, 1024, 4096)) // 4 * 4
    expected = per_azimuth * azimuths
    assert expected > 3.0, f"a bake of {expected:.1f} s is too short to interrupt"
    sent = []

    def interrupt():
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)

    timer = threading.Timer(0.5, interrupt)
    start = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            aperture.bake(big_dem, 10.0, azimuths=azimuths)
        raised = time.perf_counter()
    finally:
        timer.cancel()
    assert sent, "the bake ended before the signal"
    assert raised - sent[0] < 1.0, f"KeyboardInterrupt {raised - sent[0]:.2f} s after SIGINT"
    assert raised - start < expected / 2
    # The module is usable again, and the interrupt left nothing behind.
    small = aperture.bake(big_dem[:64, :64], 10.0)
    assert np.isfinite(small.sky_view_factor).all()


def test_ctrl_c_stops_a_relief(big_dem):
    sent = []

    def interrupt():
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)

    # The relief's bake (64 azimuths) and shading of 4096 x 1024 texels: seconds.
    dem = np.tile(big_dem, (1, 4))
    timer = threading.Timer(0.3, interrupt)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            aperture.relief(dem, 10.0)
        raised = time.perf_counter()
    finally:
        timer.cancel()
    assert sent and raised - sent[0] < 1.0


def test_a_progress_callback_that_raises_stops_the_relief_in_its_shading():
    # The shading reports after each band of rows and each pass (obscurance, then
    # light): a stop asked for during its first pass ends it at the second. The
    # stop is asked at the first report of 0.5 or more: the callback runs every
    # 50 ms, and the light pass (0.75 to 1) can end within that, so waiting for
    # a fraction above 0.5 could first see 1.0, the relief already done.
    z = np.tile(np.linspace(0, 200, 768, dtype=np.float32), (768, 1))
    seen = []

    def stop_in_the_shading(fraction):
        seen.append(fraction)
        if fraction >= 0.5:  # the bake is [0, 0.5], the shading (0.5, 1]
            raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        aperture.relief(z, 10.0, progress=stop_in_the_shading)
    assert seen[-1] < 1.0
