# SPDX-License-Identifier: Apache-2.0
"""Frames of any numeric type a user has (float64 from numpy, uint8 from cv2.imread) come back in
their own type, or are refused with a ValueError naming them; the likely unit mistakes get a message
that names the argument and the unit."""
import numpy as np
import pytest

from conftest import make_scene


def test_float64_frames_go_through_and_come_back_float64(db, small_setup):
    plant, sched, cam, shutter = small_setup
    sharp = make_scene(120, 160).astype(np.float64)
    blurred = db.renderBlurred(sharp, plant, sched, cam, shutter)
    assert blurred.dtype == np.float64
    deblurrer = db.DynamicDeblurrer.create(plant, cam)
    deblurrer.setPsfModel(db.PSF_ROWS)
    restored = deblurrer.deblur(blurred, sched, shutter)
    assert restored.dtype == np.float64 and restored.shape == blurred.shape
    single = deblurrer.deblur(blurred.astype(np.float32), sched, shutter)
    assert single.dtype == np.float32
    np.testing.assert_allclose(restored, single, atol=1e-6)
    restored, valid = deblurrer.deblur(blurred, sched, shutter, returnMask=True)
    assert restored.dtype == np.float64 and valid.dtype == np.uint8


def test_uint8_frames_come_back_uint8(db, small_setup):
    plant, sched, cam, shutter = small_setup
    blurred = db.renderBlurred(make_scene(120, 160), plant, sched, cam, shutter)
    frame = np.clip(db.linearToSrgb(blurred), 0, 255).astype(np.uint8)
    restored = db.DynamicDeblurrer.create(plant, cam).deblur(frame, sched, shutter)
    assert restored.dtype == np.uint8


def test_other_frame_dtypes_raise_value_error(db, small_setup):
    plant, sched, cam, shutter = small_setup
    deblurrer = db.DynamicDeblurrer.create(plant, cam)
    for dtype in (np.int16, np.uint16, np.float16):
        with pytest.raises(ValueError, match="'frame'.*uint8.*float64"):
            deblurrer.deblur(np.zeros((120, 160), dtype), sched, shutter)
    with pytest.raises(ValueError, match="'still'"):
        deblurrer.setReferenceFrame(np.zeros((120, 160), np.int32))


def test_unit_mistakes_name_argument_and_unit(db, small_setup):
    plant, sched, cam, shutter = small_setup
    with pytest.raises(db.error, match="gain.*radians per level.*degrees"):
        db.Plant.create(naturalFreqHz=14.4, dampingRatio=0.12, gain=1.0)  # 1 degree meant
    with pytest.raises(db.error, match="toAngle.*radians expected"):
        db.SwitchPlanner.create(plant, maxLevel=16).plan(0.0, 10.0, startTime=0.0)  # degrees given
    sharp = make_scene(120, 160)
    with pytest.raises(db.error, match="thetaRef.*radians expected"):
        db.renderBlurred(sharp, plant, sched, cam, shutter, thetaRef=10)
    ms = db.RollingShutter(frameStart=shutter.frameStart, exposure=8, lineDelay=shutter.lineDelay, rows=120)
    with pytest.raises(db.error, match="exposure.*seconds.*ms"):
        db.DynamicDeblurrer.create(plant, cam).deblur(sharp, sched, ms)
    us = db.RollingShutter(frameStart=shutter.frameStart, exposure=0.008, lineDelay=62.5, rows=120)
    with pytest.raises(db.error, match="lineDelay.*seconds"):
        db.renderBlurred(sharp, plant, sched, cam, us)
    t = np.linspace(0.0, 0.3, 301)
    theta_deg = np.rad2deg(plant.response(sched, t))
    with pytest.raises(db.error, match="theta.*radians expected.*degrees"):
        db.Plant.identify(t, theta_deg, sched)


def test_unobserved_pixels_keep_the_recorded_frame_by_default(db, small_setup):
    plant, sched, cam, shutter = small_setup
    blurred = db.renderBlurred(make_scene(120, 160), plant, sched, cam, shutter)
    deblurrer = db.DynamicDeblurrer.create(plant, cam)
    assert deblurrer.getUnobservedFill() == db.UNOBSERVED_RECORDED
    restored, valid = deblurrer.deblur(blurred, sched, shutter, returnMask=True)
    unobserved = valid == 0
    assert unobserved.sum() > 160, "no unobserved band: the test proves nothing"
    np.testing.assert_array_equal(restored[unobserved], blurred[unobserved])
    deblurrer.setUnobservedFill(db.UNOBSERVED_MARKED)
    marked = deblurrer.deblur(blurred, sched, shutter)
    assert np.all(marked[unobserved] == 0)
