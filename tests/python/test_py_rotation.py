# SPDX-License-Identifier: Apache-2.0
"""Any camera rotation from Python: a gyroscope's 3-axis motion through the forward model, the PSF
generator, the exposure windows and the deblurrer, which then needs no plant."""
import numpy as np
import pytest

import dynblur as db
from conftest import make_scene


def shake(peak_deg_per_sec=40.0):
    """A 200 Hz gyroscope log of a shake about all three camera axes: times (N,), rates (N, 3)."""
    t = np.arange(0.0, 0.4, 0.005)
    hz = np.array([3.1, 5.3, 7.9])
    rates = np.deg2rad(peak_deg_per_sec) * np.sin(2 * np.pi * hz[None, :] * t[:, None] + np.arange(3))
    return t, rates


def test_gyro_motion_through_the_pipeline():
    height, width = 120, 160
    cam = db.CameraModel.create(150.0, 150.0, 79.5, 59.5, width, height)
    motion = db.CameraMotion.fromAngularVelocity(*shake())
    shutter = db.RollingShutter(frameStart=0.1, exposure=0.02, lineDelay=0.03 / height, rows=height)
    assert db.classifyExposure(motion, shutter) == db.EXPOSURE_II
    sharp = make_scene(height + 32, width + 32)
    blurred = db.renderBlurred(sharp, motion, cam, shutter)
    assert blurred.shape == (height, width, 3) and blurred.dtype == np.float32
    bank = db.PsfGenerator.create(cam).generate(db.PSF_TILES, motion, shutter)
    assert len(bank.kernels) == len(bank.nodeRows) * len(bank.nodeCols) and bank.maxKernelSize()[0] > 1
    deblurrer = db.DynamicDeblurrer.create(cam)
    restored, valid = deblurrer.deblur(blurred, motion, shutter, returnMask=True)
    truth = sharp[16:-16, 16:-16]
    inner = (slice(8, -8), slice(8, -8))
    err_blurred = np.mean(np.abs(blurred - truth)[inner])
    err_restored = np.mean(np.abs(restored - truth)[inner])
    print(f"3-axis shake: mean |error| blurred {err_blurred:.4f}, restored {err_restored:.4f}")
    assert err_restored < 0.8 * err_blurred
    assert valid.dtype == np.uint8 and valid.shape == (height, width)
    # A view turned by the motion's relative rotation maps pixels as the rotation form says.
    R = motion.relativeRotation(0.12, motion.referenceOrientation(float("nan"), shutter))
    q = cam.viewToReference(np.array([[79.5, 59.5]]), R)
    assert q.shape == (1, 2) and np.all(np.isfinite(q))


def test_plantless_deblurrer_and_bad_motion_arguments():
    cam = db.CameraModel.create(150.0, 150.0, 79.5, 59.5, 160, 120)
    motion = db.CameraMotion.fromAngularVelocity(*shake())
    frame = np.full((120, 160, 3), 0.5, np.float32)
    sched = db.SwitchSchedule(times=[0.0], levels=[4], initialLevel=0)
    deblurrer = db.DynamicDeblurrer.create(cam)
    with pytest.raises(db.error, match="without a plant"):
        deblurrer.deblur(frame, sched, db.RollingShutter(0.0, 0.01, 0.0, 120))
    with pytest.raises(db.error, match="time span"):
        deblurrer.deblur(frame, motion, db.RollingShutter(0.5, 0.01, 0.0, 120))
    with pytest.raises(ValueError, match="motion"):
        db.renderBlurred(frame, None, cam, db.RollingShutter(0.1, 0.01, 0.0, 120))
    with pytest.raises(db.error, match="rotation"):
        cam.viewToReference(np.zeros((1, 2)), np.diag([1.0, 1.0, -1.0]))
