# SPDX-License-Identifier: Apache-2.0
"""CameraMotion and GyroLog from Python: numpy shapes in, 3×3 rotations out, bad input refused."""
import math

import numpy as np
import pytest


def rotation_about(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def test_from_angular_velocity_constant_axis(db):
    axis = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    t = np.linspace(0.0, 1.0, 201)
    rates = np.outer(np.full_like(t, 0.7), axis)
    motion = db.CameraMotion.fromAngularVelocity(t, rates)
    q = motion.orientation(0.5)
    assert isinstance(q, np.ndarray) and q.shape == (3, 3)
    np.testing.assert_allclose(q, rotation_about(axis, 0.35), atol=1e-12)
    np.testing.assert_allclose(motion.angularVelocity(0.25), 0.7 * axis, atol=1e-12)
    assert motion.getTimeSpan() == (0.0, 1.0)
    assert not motion.isPlantMotion()
    shutter = db.RollingShutter(frameStart=0.2, exposure=0.01, lineDelay=1e-4, rows=101)
    np.testing.assert_allclose(motion.referenceOrientation(math.nan, shutter),
                               motion.orientation(0.2 + 50e-4 + 0.005), atol=1e-15)


def test_from_orientations_accepts_every_form(db):
    t = np.array([0.0, 0.1, 0.2, 0.3])
    rotvecs = np.array([[0, 0, 0], [0.1, 0, 0.05], [0.2, -0.1, 0.1], [0.25, -0.2, 0.1]])
    matrices = np.array([rotation_about(r, np.linalg.norm(r)) if np.linalg.norm(r) > 0 else np.eye(3)
                         for r in rotvecs])
    quats = []
    for r in rotvecs:
        a = np.linalg.norm(r)
        quats.append([math.cos(a / 2), *(r / a * math.sin(a / 2) if a > 0 else np.zeros(3))])
    forms = [rotvecs, np.array(quats), matrices, matrices.reshape(4, 9)]
    motions = [db.CameraMotion.fromOrientations(t, f) for f in forms]
    for m in motions[1:]:
        np.testing.assert_allclose(m.orientation(0.17), motions[0].orientation(0.17), atol=1e-12)
    np.testing.assert_allclose(motions[0].orientation(0.2), matrices[2], atol=1e-12)


def test_from_plant(db):
    plant = db.Plant.create(14.4, 0.12, math.radians(1))
    sched = db.SwitchSchedule([0.0], [10], 0)
    motion = db.CameraMotion.fromPlant(plant, sched, (0, 1, 0))
    assert motion.isPlantMotion()
    theta = plant.response(sched, np.array([0.03]))[0]
    np.testing.assert_allclose(motion.orientation(0.03), rotation_about([0, 1, 0], theta), atol=1e-12)
    with pytest.raises(ValueError, match="'plant' is None"):
        db.CameraMotion.fromPlant(None, sched)


def test_bad_input(db):
    t = np.linspace(0.0, 0.1, 11)
    with pytest.raises(ValueError, match="'rates' must have shape"):
        db.CameraMotion.fromAngularVelocity(t, np.zeros((11, 2)))
    with pytest.raises(ValueError, match="'rotations' must have shape"):
        db.CameraMotion.fromOrientations(t, np.zeros((11, 5)))
    with pytest.raises(ValueError, match="'times' must have shape"):
        db.CameraMotion.fromAngularVelocity(t.reshape(1, -1, 1), np.zeros((11, 3)))
    with pytest.raises(db.error, match="strictly increasing"):
        db.CameraMotion.fromAngularVelocity(t[::-1].copy(), np.zeros((11, 3)))
    motion = db.CameraMotion.fromAngularVelocity(t, np.zeros((11, 3)))
    with pytest.raises(db.error, match="outside the motion's time span"):
        motion.orientation(0.2)


def test_gyro_log(db, tmp_path):
    path = tmp_path / "log.gcsv"
    lines = ["GYROFLOW IMU LOG", "version,1.3", "id,pytest", "orientation,YxZ", "tscale,0.001", "gscale,0.01",
             "t,gx,gy,gz"] + [f"{k * 5},{10},{20},{30}" for k in range(201)]
    path.write_text("\n".join(lines) + "\n")
    log = db.GyroLog.load(str(path))
    assert log.id == "pytest" and log.orientation == "YxZ"
    assert log.times.shape == (201,) and log.rates.shape == (201, 3)
    np.testing.assert_allclose(log.rates[0], [0.2, -0.1, 0.3])
    np.testing.assert_allclose(log.cameraFromGyro, db.GyroLog.orientationMatrix("YxZ"))
    np.testing.assert_allclose(log.toMotion().angularVelocity(0.5), [0.2, -0.1, 0.3], atol=1e-15)
    # A constant rate read as a bias (a threshold above it): the corrected motion stands still.
    options = db.GyroLogOptions()
    options.estimateBias = True
    options.stillThreshold = 0.5
    log = db.GyroLog.load(str(path), options)
    np.testing.assert_allclose(log.bias, [0.2, -0.1, 0.3])
    np.testing.assert_allclose(log.toMotion().orientation(1.0), np.eye(3), atol=1e-14)
    path.write_text("t,gx,gy,gz\n0,0,0,0\n0.005,0,0\n")
    with pytest.raises(db.error, match="log.gcsv:3"):
        db.GyroLog.load(str(path))
