# SPDX-License-Identifier: Apache-2.0
"""A gyro log's clock from Python: the bias flag and field, a recording's calibrateTiming on a
CameraMotion, a frame refined against a still placed by its capture time, and bad input named."""
import numpy as np
import pytest

from conftest import make_scene

OFFSET = 0.004  # s: the log's clock ahead of the camera's


def shake(t):
    """Body rates (N, 3), rad/s: two sines per axis, about 30 deg/s peak."""
    hz = np.array([[3.1, 11.0], [2.3, 7.7], [4.4, 16.5]])
    phase = np.array([[0.4, 2.0], [1.3, 0.2], [2.9, 1.1]])
    t = np.asarray(t)[:, None, None]
    return np.deg2rad(15.0) * np.cos(2 * np.pi * hz * t + phase).sum(axis=2)


@pytest.fixture(scope="module")
def recording(db):
    """160x120 at fx = 150 px: four 20 ms rolling frames with a still 0.1 s before each, the truth
    integrated at 1 kHz, and a 200 Hz log OFFSET ahead."""
    cam = db.CameraModel.create(150.0, 150.0, 79.5, 59.5, 160, 120)
    dense = np.arange(-0.5, 0.8, 1e-3)
    truth = db.CameraMotion.fromAngularVelocity(dense, shake(dense))
    times = np.arange(-0.4, 0.7, 5e-3)
    log = db.CameraMotion.fromAngularVelocity(times, shake(times - OFFSET))
    scene = make_scene(120 + 2 * 24, 160 + 2 * 24, channels=1, seed=5)
    frames, stills, shutters, still_shutters = [], [], [], []
    for i in range(4):
        start = -0.1 + 0.13 * i
        shutter = db.RollingShutter(frameStart=start, exposure=0.02, lineDelay=0.03 / 120, rows=120)
        still = db.RollingShutter(frameStart=start - 0.1, exposure=1e-4, lineDelay=0.0, rows=120)
        mid = start + 0.5 * 119 * 0.03 / 120 + 0.01
        frames.append(db.addSensorNoise(db.renderBlurred(scene, truth, cam, shutter, tRef=mid), seed=10 + i))
        stills.append(db.addSensorNoise(db.renderBlurred(scene, truth, cam, still, tRef=mid), seed=20 + i))
        shutters.append(shutter)
        still_shutters.append(still)
    return cam, log, frames, stills, shutters, still_shutters


def test_bias_flag_and_fields(db):
    assert db.REFINE_GYRO_BIAS == 8
    c = db.MotionCorrection()
    assert tuple(c.gyroBias) == (0.0, 0.0, 0.0)
    c.gyroBias = (0.01, -0.01, 0.0)
    assert tuple(c.gyroBias) == pytest.approx((0.01, -0.01, 0.0))
    assert "gyroBias=(0.01" in repr(c)
    assert tuple(db.TimingCalibration().gyroBiasStd) == (0.0, 0.0, 0.0)


def test_recording_calibration_finds_the_offset(db, recording):
    cam, log, frames, stills, shutters, still_shutters = recording
    t = db.calibrateTiming(log, cam, stills, frames, shutters, still_shutters, flags=db.REFINE_TIME_OFFSET,
                           maxTimeOffset=0.01)
    assert t.correction.timeOffset == pytest.approx(OFFSET, abs=0.5e-3)
    assert len(t.scanObjective) == len(t.scanTimeOffsets) > 0
    assert list(t.frameUsed) == [1, 1, 1, 1]


def test_frame_refined_against_a_still_placed_by_time(db, recording):
    cam, log, frames, stills, shutters, still_shutters = recording
    deblurrer = db.DynamicDeblurrer.create(cam)
    deblurrer.setReferenceFrame(stills[1], still_shutters[1])
    deblurrer.setRefinement(db.REFINE_TIME_OFFSET)
    restored = deblurrer.deblur(frames[1], log, shutters[1])
    c = deblurrer.getLastCorrection()
    assert restored.shape == frames[1].shape
    assert c.applied, c.reason
    assert c.timeOffset == pytest.approx(OFFSET, abs=1e-3)


def test_bad_input_is_named(db, recording):
    cam, log, frames, stills, shutters, still_shutters = recording
    with pytest.raises(Exception, match="referenceShutters"):
        db.calibrateTiming(log, cam, stills, frames, shutters, still_shutters[:2])
    with pytest.raises(Exception, match="flags = 4"):
        db.calibrateTiming(log, cam, stills, frames, shutters, still_shutters, flags=db.REFINE_PLANT)
    deblurrer = db.DynamicDeblurrer.create(cam)
    deblurrer.setReferenceFrame(stills[0], 0.0)  # an angle: a plant's still
    with pytest.raises(Exception, match="capture time"):
        deblurrer.deblur(frames[0], log, shutters[0])
