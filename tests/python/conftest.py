# SPDX-License-Identifier: Apache-2.0
"""Shared fixtures of the Python binding tests (test_py_*.py): a small camera, plant and scene."""
import importlib
import os

import numpy as np
import pytest


def data_required():
    """True under the test command (DYNBLUR_REQUIRE_TEST_DATA=1): what a figure needs must be there."""
    return os.environ.get("DYNBLUR_REQUIRE_TEST_DATA") == "1"


@pytest.fixture(scope="session")
def require_data():
    """require_data(found, message): a failure when `found` is false under DYNBLUR_REQUIRE_TEST_DATA=1
    (a CI run without the data must not pass by skipping), else a skip with the message."""
    def check(found, message):
        if found:
            return
        if data_required():
            pytest.fail(f"{message} (DYNBLUR_REQUIRE_TEST_DATA=1: missing data is a failure)")
        pytest.skip(message)
    return check


@pytest.fixture(scope="session")
def db():
    # Under the test command the bindings are built first: their absence is a failure, not a skip.
    if data_required():
        return importlib.import_module("dynblur")
    return pytest.importorskip("dynblur")


def make_scene(height, width, channels=3, seed=0):
    """A textured float32 scene in [0.05, 0.95]: bars, disks and smooth noise."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:height, 0:width].astype(np.float32)
    img = 0.5 + 0.25 * np.sign(np.sin(x / 7.0)) * np.sign(np.sin(y / 11.0))
    for _ in range(12):
        cy, cx, r = rng.uniform(0, height), rng.uniform(0, width), rng.uniform(3, height / 6)
        img = np.where((y - cy) ** 2 + (x - cx) ** 2 < r * r, rng.uniform(0.1, 0.9), img)
    img = np.clip(img, 0.05, 0.95).astype(np.float32)
    if channels == 1:
        return img
    tint = np.array([1.0, 0.85, 0.7, 1.0][:channels], np.float32)
    return np.clip(img[..., None] * tint, 0.05, 0.95).astype(np.float32)


def window_start(db, plant, sched, rows, exposure, line_delay, window):
    """A frame start (s) whose readout falls in the requested exposure window."""
    for start in np.arange(-0.06, 0.08, 0.0005):
        sh = db.RollingShutter(frameStart=float(start), exposure=exposure, lineDelay=line_delay, rows=rows)
        if db.classifyExposure(plant, sched, sh) == window:
            return float(start)
    raise AssertionError(f"no frame start gives window {window}")


@pytest.fixture(scope="session")
def small_setup(db):
    """160×120 camera (a C270 at 1/8 of its resolution), the seed plant, a 10° fast plan."""
    plant = db.Plant.create(naturalFreqHz=14.4, dampingRatio=0.12, gain=np.deg2rad(1.0))
    sched = db.SwitchPlanner.create(plant, maxLevel=16).plan(0.0, np.deg2rad(10), startTime=0.0)
    cam = db.CameraModel.create(154.0, 154.0, 79.5, 59.5, 160, 120)
    line_delay = 0.030 / 120
    start = window_start(db, plant, sched, 120, 0.008, line_delay, db.EXPOSURE_III)
    shutter = db.RollingShutter(frameStart=start, exposure=0.008, lineDelay=line_delay, rows=120)
    return plant, sched, cam, shutter
