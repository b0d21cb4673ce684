# SPDX-License-Identifier: Apache-2.0
"""MultiAxisDriver from Python against the simulator program: a controller of two axes, every axis
verified, one START for both; the refusals of a count mismatch.

The simulator ``dynblur_actuator_sim`` is found in $DYNBLUR_BUILD_DIR/samples (default build/ beside
the repository) or at $DYNBLUR_ACTUATOR_SIM.
"""
import os
import pathlib
import re
import subprocess
import time

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


def sim_path():
    explicit = os.environ.get("DYNBLUR_ACTUATOR_SIM")
    if explicit:
        return pathlib.Path(explicit)
    return pathlib.Path(os.environ.get("DYNBLUR_BUILD_DIR", REPO / "build")) / "samples" / "dynblur_actuator_sim"


@pytest.fixture
def two_axis_sim():
    """The simulator of two axes on a free loopback port: yields its URI."""
    tool = sim_path()
    if not tool.exists():
        pytest.fail(f"{tool} not found: build the dynblur_actuator_sim target or set DYNBLUR_BUILD_DIR")
    proc = subprocess.Popen([str(tool), "--axes", "2", "--tcp-port", "0", "--csv", "", "--max-seconds", "60",
                             "--status-every", "0"], stdout=subprocess.PIPE, text=True)
    try:
        uri = None
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and uri is None:
            line = proc.stdout.readline()
            m = re.search(r"\(uri (tcp://[^)]*)\)", line)
            if m:
                uri = m.group(1)
        assert uri, "the simulator printed no URI"
        yield uri
    finally:
        proc.terminate()
        proc.wait(10)


def moves(db):
    return [db.SwitchSchedule([0.0, 0.0113, 0.0262, 0.04], [4, 10, 7, 10], 0),
            db.SwitchSchedule([0.0, 0.015, 0.03], [-3, -6, -5], 0)]


def test_two_axes_start_together(db, two_axis_sim):
    driver = db.MultiAxisDriver.create(db.ActuatorBus.create(two_axis_sim, 2.0), 2)
    info = driver.connect()
    assert info.axes == 2 and (info.protocolMajor, info.protocolMinor) == (1, 1)
    before = time.monotonic()
    driver.upload(moves(db))
    assert [s.state for s in driver.statusAll()] == [db.ACTUATOR_LOADED] * 2
    reports = driver.start()
    assert len(reports) == 2
    assert reports[0].controllerStartTime == reports[1].controllerStartTime  # one START, one instant
    assert before <= reports[0].hostStartTime <= time.monotonic()
    done = driver.waitUntilDone(2.0)
    assert [(s.state, s.currentLevel) for s in done] == [(db.ACTUATOR_DONE, 10), (db.ACTUATOR_DONE, -5)]
    assert driver.status(1).describe() == "DONE, level -5, entry 2"


def test_count_mismatches_are_refused(db, two_axis_sim):
    bus = db.ActuatorBus.create(two_axis_sim, 2.0)
    with pytest.raises(db.error, match="has 2 axes, the host asks for 3"):
        db.MultiAxisDriver.create(bus, 3).connect()
    driver = db.MultiAxisDriver.create(bus, 2)
    driver.connect()
    with pytest.raises(db.error, match="1 schedules for 2 axes"):
        driver.upload(moves(db)[:1])
    with pytest.raises(db.error, match="no verified schedules"):
        driver.start()
    assert [s.state for s in driver.statusAll()] == [db.ACTUATOR_IDLE] * 2
    with pytest.raises(db.error, match=r"axes = 0 must be in \[1, 7\]"):
        db.MultiAxisDriver.create(bus, 0)
    with pytest.raises(ValueError, match="'bus' is None"):
        db.MultiAxisDriver.create(None, 2)
