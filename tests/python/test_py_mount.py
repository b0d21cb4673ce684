# SPDX-License-Identifier: Apache-2.0
"""Mount from Python: a pan-tilt head's orientation, pointing and its inverse, the motion of one
schedule per axis, and bad input refused."""
import math

import numpy as np
import pytest


def pan_tilt(db):
    mount = db.Mount.create()
    mount.addAxis((0, 1, 0), db.Plant.create(14.4, 0.12, math.radians(0.2)), -200, 200)
    mount.addAxis((1, 0, 0), db.Plant.create(11.0, 0.15, math.radians(0.25)), -120, 120)
    return mount


def test_pointing_and_its_inverse(db):
    mount = pan_tilt(db)
    assert mount.getAxisCount() == 2
    assert mount.getLevelRange(1) == (-120, 120)
    np.testing.assert_allclose(mount.getAngleRange(1), (-math.radians(30), math.radians(30)), atol=1e-15)
    target = [math.radians(12.0), math.radians(-7.0)]
    q = mount.orientation(target)
    assert isinstance(q, np.ndarray) and q.shape == (3, 3)
    np.testing.assert_allclose(mount.pointing(target), q[:, 2], atol=1e-15)
    np.testing.assert_allclose(mount.anglesFor(mount.pointing(target)), target, atol=1e-12)


def test_motion_follows_each_axis_schedule(db):
    mount = pan_tilt(db)
    schedules = [db.SwitchPlanner.create(mount.getPlant(0), 200).plan(0.0, math.radians(5), 0.0),
                 db.SwitchPlanner.create(mount.getPlant(1), 120).plan(0.0, math.radians(-4), 0.0)]
    motion = mount.motion(schedules)
    assert not motion.isPlantMotion()
    rest = [mount.getPlant(i).restingAngle(schedules[i].levels[-1]) for i in range(2)]
    np.testing.assert_allclose(motion.orientation(2.0), mount.orientation(rest), atol=1e-9)
    assert np.linalg.norm(motion.angularVelocity(0.01)) > 0.1


def test_bad_input_is_refused(db):
    mount = pan_tilt(db)
    with pytest.raises(Exception, match="angles has 1 values for 2 axes"):
        mount.orientation([0.1])
    with pytest.raises(Exception, match="no joint angles the axes reach"):
        mount.anglesFor((0, -1, 0))
    with pytest.raises(ValueError, match="plant"):
        mount.addAxis((1, 0, 0), None, 0, 1)


def test_mount_file_round_trip_and_refusal(db, tmp_path):
    mount = pan_tilt(db)
    path = str(tmp_path / "mount.yml")
    mount.save(path)
    back = db.Mount.load(path)
    assert back.getAxisCount() == 2
    assert back.getLevelRange(0) == (-200, 200)
    np.testing.assert_array_equal(back.getAxis(1), (1, 0, 0))
    assert back.getPlant(1).getNaturalFreqHz() == 11.0
    bad = tmp_path / "bad.yml"
    bad.write_text(open(path).read().replace("axis1_levels: [ -120, 120 ]", "axis1_levels: [ 120, -120 ]"))
    with pytest.raises(Exception, match="axis1_levels must be"):
        db.Mount.load(str(bad))
