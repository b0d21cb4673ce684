# SPDX-License-Identifier: Apache-2.0
"""MountPlanner from Python: a diagonal saccade of the shipped pan-tilt head, coordinated and
independent, pointing at a pixel, and bad input refused."""
import math
import pathlib

import pytest

PAN_TILT = pathlib.Path(__file__).resolve().parents[2] / "samples" / "data" / "pan_tilt.yml"


def test_diagonal_saccade_coordinated_and_independent(db):
    mount = db.Mount.load(str(PAN_TILT))
    to = [math.radians(10), math.radians(6)]
    together = db.MountPlanner.create(mount).plan([0.0, 0.0], to)
    apart = db.MountPlanner.create(mount, db.PLAN_FAST, 0.002, db.MOUNT_INDEPENDENT).plan([0.0, 0.0], to)
    assert len(together.schedules) == 2
    assert together.toAngles == pytest.approx(to, abs=1e-12)
    assert max(together.residualVibration) <= 0.01
    assert together.settleTime == pytest.approx(max(together.axisSettleTimes))
    assert together.settleTime <= 1.1 * apart.settleTime
    assert together.pathDeviation <= apart.pathDeviation
    assert together.peakRate > 0


def test_points_at_a_pixel(db):
    mount = db.Mount.load(str(PAN_TILT))
    camera = db.CameraModel.create(615, 615, 319.5, 239.5, 640, 480)
    planner = db.MountPlanner.create(mount)
    assert planner.getCoordination() == db.MOUNT_COORDINATED
    move = planner.planToPixel(camera, (319.5 + 615 * math.tan(math.radians(5)), 239.5), [0.0, 0.0])
    assert move.toAngles == pytest.approx([math.radians(5), 0.0], abs=1e-9)


def test_bad_input_is_refused(db):
    planner = db.MountPlanner.create(db.Mount.load(str(PAN_TILT)))
    with pytest.raises(Exception, match=r"toAngles\[1\] = .* is outside axis 1's range"):
        planner.plan([0.0, 0.0], [0.0, math.radians(20)])
    with pytest.raises(Exception, match="fromAngles has 1 values for 2 axes"):
        planner.plan([0.0], [0.0, 0.0])
    with pytest.raises(Exception, match="must be finite"):
        planner.plan([0.0, float("nan")], [0.0, 0.0])
    with pytest.raises(ValueError, match="mount"):
        db.MountPlanner.create(None)
