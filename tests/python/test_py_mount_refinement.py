# SPDX-License-Identifier: Apache-2.0
"""A mount's motion refined from Python: each axis's plant scales in the refinement's table, a
pan-tilt frame refined against the stills at rest on both sides of its move, a pan-only move that
holds the tilt's parameters, and a recording calibrated."""
import math

import numpy as np
import pytest

from conftest import make_scene


def pan_tilt(db, pan=(1.0, 1.0), tilt=(1.0, 1.0)):
    """Pan (0, 1, 0) carries tilt (1, 0, 0), each the seed's positioner scaled by (wn, zeta)."""
    mount = db.Mount.create()
    mount.addAxis((0, 1, 0), db.Plant.create(14.4 * pan[0], 0.12 * pan[1], math.radians(1)), -16, 16)
    mount.addAxis((1, 0, 0), db.Plant.create(14.4 * tilt[0], 0.12 * tilt[1], math.radians(1)), -16, 16)
    return mount


def saccade(db, pan_deg, tilt_deg):
    nominal = pan_tilt(db)
    return [db.SwitchPlanner.create(nominal.getPlant(i), 16).plan(0.0, math.radians(d), 0.0) if d else
            db.SwitchSchedule([0.0], [0]) for i, d in enumerate((pan_deg, tilt_deg))]


@pytest.fixture(scope="module")
def head(db):
    """160x120 at fx = 300 px, a scene wide enough for a 10 degree pan and a 6 degree tilt."""
    cam = db.CameraModel.create(300.0, 300.0, 79.5, 59.5, 160, 120)
    return cam, make_scene(120 + 2 * 48, 160 + 2 * 72, channels=1, seed=5)


def window_iii(db, motion, line_delay):
    """The middle of the frame starts (0.25 ms steps) whose frame ends at rest."""
    starts = [k * 2.5e-4 for k in range(400)
              if db.classifyExposure(motion, db.RollingShutter(k * 2.5e-4, 0.008, line_delay, 120)) ==
              db.EXPOSURE_III]
    assert starts
    return db.RollingShutter(0.5 * (starts[0] + starts[-1]), 0.008, line_delay, 120)


def capture(db, head, motion, shutter, seed):
    cam, scene = head
    return db.addSensorNoise(db.renderBlurred(scene, motion, cam, shutter), seed=seed)


def late_frame(db, head, pan_deg, tilt_deg):
    """A window III frame of a drifted head (pan wn +3 %, zeta +10 %; tilt wn -3 %, zeta -10 %) 1 ms
    later than told: the motion told, the shutter told, the frame and the still after the move."""
    schedules = saccade(db, pan_deg, tilt_deg)
    told = pan_tilt(db).motion(schedules)
    truth = pan_tilt(db, (1.03, 1.10), (0.97, 0.90)).motion(schedules)
    line_delay = 1 / 30 / 120
    shutter = window_iii(db, told, line_delay)
    late = db.RollingShutter(shutter.frameStart + 1e-3, 0.008, line_delay, 120)
    still = capture(db, head, truth, db.RollingShutter(1.0, 0.008, line_delay, 120), 2)
    return told, shutter, capture(db, head, truth, late, 1), still


def test_table_has_each_axis(db):
    rows = [p for p in db.refinementParameters() if p.mountAxis >= 0]
    assert {p.mountAxis for p in rows} == {0, 1, 2}
    assert all(p.flag == db.REFINE_PLANT and p.mountMotion for p in rows)
    c = db.MotionCorrection()
    assert c.axisNaturalFreqScales == (1.0, 1.0) and c.axisDampingScales == (1.0, 1.0) and c.heldParameters == 0


def test_correct_motion_scales_each_axis(db):
    schedules = saccade(db, 10, 6)
    c = db.MotionCorrection(naturalFreqScale=1.03, dampingScale=1.10)
    c.axisNaturalFreqScales = (0.97, 1.0)
    c.axisDampingScales = (0.90, 1.0)
    corrected = c.correctMotion(pan_tilt(db).motion(schedules))
    truth = pan_tilt(db, (1.03, 1.10), (0.97, 0.90)).motion(schedules)
    np.testing.assert_allclose(corrected.orientation(0.03), truth.orientation(0.03), atol=1e-12)


def test_mount_frame_is_refined(db, head):
    cam, _ = head
    told, shutter, frame, still = late_frame(db, head, 10, 6)
    d = db.DynamicDeblurrer.create(cam)
    d.setReferenceFrames(None, still)
    restored = d.deblur(frame, told, shutter)
    c = d.getLastCorrection()
    assert restored.shape == frame.shape and c.applied, c.reason
    assert c.reason.startswith("refined against the still after the move"), c.reason
    assert c.timeOffset == pytest.approx(1e-3, abs=0.5e-3)


def test_pan_only_move_holds_the_tilt(db, head):
    cam, _ = head
    told, shutter, frame, still = late_frame(db, head, 10, 0)
    d = db.DynamicDeblurrer.create(cam)
    d.setReferenceFrames(None, still)
    d.deblur(frame, told, shutter)
    c = d.getLastCorrection()
    tilt = [j for j, p in enumerate(db.refinementParameters()) if p.mountAxis == 1]
    assert all(c.heldParameters & (1 << j) for j in tilt), c.reason
    assert c.axisNaturalFreqScales == (1.0, 1.0) and c.axisDampingScales == (1.0, 1.0)


def test_recording_is_calibrated(db, head):
    cam, _ = head
    frames = [late_frame(db, head, 10, 6), late_frame(db, head, 10, 0)]
    t = db.calibrateTiming([f[0] for f in frames], cam, [f[3] for f in frames], [f[2] for f in frames],
                           [f[1] for f in frames], db.REFINE_TIME_OFFSET | db.REFINE_PLANT, [1, 1])
    assert t.frameUsed == [1, 1]
    assert t.correction.timeOffset == pytest.approx(1e-3, abs=0.5e-3)
    with pytest.raises(db.error, match="motions\\[0\\] is not a mount's"):
        db.calibrateTiming([db.CameraMotion.fromPlant(db.Plant.create(14.4, 0.12, 0.01), db.SwitchSchedule([0.0], [0]))], cam,
                           [frames[0][3]], [frames[0][2]], [frames[0][1]])
