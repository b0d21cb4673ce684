# SPDX-License-Identifier: Apache-2.0
"""GyroLog.fromVideo and python -m dynblur.extract_gyro (dynblur/extract_gyro.py over telemetry-parser),
and GyroLog.load's phone-app layouts checked against telemetry-parser's reading of the same files.

No video is downloaded: the parser reads gcsv, Sensor Logger and OpenCamera Sensors files too, so the
end-to-end tests give it small files written here; the conversion from the parser's structures is
tested on structures shaped as telemetry-parser 0.3.0 returns them (dynblur/extract_gyro.py's docstring)."""
import math
import os
import subprocess
import sys

import numpy as np
import pytest
import telemetry_parser

DEG = math.pi / 180


def camera_from_gyroflow(w):
    """Gyroflow's frame (x up, y left, z backward) to camera axes (x right, y down, z forward)."""
    w = np.asarray(w, dtype=float)
    return np.stack([-w[..., 1], -w[..., 0], -w[..., 2]], axis=-1)


def parser_imu(times_ms, rates_deg_s):
    """Samples shaped as Parser.normalized_imu() returns them, with an accelerometer-only one between."""
    imu = []
    for t, w in zip(times_ms, rates_deg_s):
        imu.append({"timestamp_ms": float(t), "gyro": tuple(float(v) for v in w), "accl": (0.0, 0.0, 9.8), "magn": None})
        imu.append({"timestamp_ms": float(t) + 0.5, "gyro": None, "accl": (0.0, 0.0, 9.8), "magn": None})
    return imu


def write_gcsv_input(path, n=200):
    """A gcsv log whose axis string is not XYZ, with a readout, that telemetry-parser reads."""
    rng = np.random.default_rng(3)
    raw = rng.integers(-2000, 2000, size=(n, 3))
    lines = ["GYROFLOW IMU LOG", "version,1.3", "id,test_logger", "orientation,YxZ", "frame_readout_time,15.23",
             "frame_readout_direction,0", "tscale,0.001", "gscale,0.001", "t,gx,gy,gz"]
    lines += [f"{5 * k},{r[0]},{r[1]},{r[2]}" for k, r in enumerate(raw)]
    path.write_text("\n".join(lines) + "\n")


def test_conversion_of_the_parser_structures(db, tmp_path):
    from dynblur import extract_gyro as eg
    times = np.arange(100) * 5.0
    rates = np.stack([10 + times / 50, np.full(100, -20.0), 30 * np.sin(times / 100)], axis=1)
    telemetry = [{"Default": {"Metadata": {"frame_readout_time": "15.23", "frame_readout_direction": "1"}}},
                 {"Gyroscope": {"Data": [], "Orientation": "XYZ", "Unit": "deg/s", "Scale": None}}]
    gyro = eg.gyro_from_parser_output("GoPro", "HERO9 Black", parser_imu(times, rates), telemetry)
    assert gyro.source == "GoPro HERO9 Black" and len(gyro.times_ms) == 100  # accelerometer-only samples skipped
    assert gyro.frame_readout_ms == 15.23 and gyro.frame_readout_direction == 1
    out = tmp_path / "clip.gcsv"
    log = eg.write_gcsv(gyro, out)
    text = out.read_text().splitlines()
    for line in ("id,GoPro_HERO9_Black", "orientation,XYZ", "frame_readout_time,15.23", "frame_readout_direction,1",
                 "tscale,0.001", f"gscale,{math.pi / 180!r}", "t,gx,gy,gz"):
        assert line in text
    assert log.layout == "gcsv" and log.orientation == "XYZ"
    assert log.frameReadoutTime == pytest.approx(15.23e-3, rel=1e-15)
    assert log.frameReadoutDirection == db.READOUT_BOTTOM_TO_TOP
    np.testing.assert_allclose(log.times, times * 1e-3, rtol=0, atol=1e-15)
    np.testing.assert_allclose(log.rates, camera_from_gyroflow(rates * DEG), rtol=1e-14, atol=1e-16)
    # No readout stated: the log says so.
    bare = eg.gyro_from_parser_output(None, "logger", parser_imu(times, rates), [])
    assert bare.frame_readout_ms is None
    assert math.isnan(eg.write_gcsv(bare, tmp_path / "bare.gcsv").frameReadoutTime)


def test_parser_output_that_is_refused(db, tmp_path):
    from dynblur import extract_gyro as eg
    with pytest.raises(ValueError, match="no gyroscope samples"):
        eg.gyro_from_parser_output("cam", None, [{"timestamp_ms": 0.0, "gyro": None}], [])
    with pytest.raises(ValueError, match="IMU sample 1"):
        eg.gyro_from_parser_output("cam", None, [{"timestamp_ms": 0.0, "gyro": (0, 0, 0)},
                                                 {"timestamp_ms": 1.0, "gyro": (0, float("nan"), 0)}], [])
    with pytest.raises(ValueError, match="frame_readout_direction 7"):
        eg.gyro_from_parser_output("cam", None, parser_imu([0, 5], [(0, 0, 0)] * 2),
                                   [{"Default": {"Metadata": {"frame_readout_direction": "7"}}}])
    # A log the reader refuses (a repeated time) is not written, and no scratch file stays behind.
    gyro = eg.gyro_from_parser_output("cam", None, parser_imu([0, 5, 5, 10], [(0, 0, 1), (0, 0, 1), (0, 0, 2),
                                                                              (0, 0, 1)]), [])
    out = tmp_path / "refused.gcsv"
    with pytest.raises(db.error, match="strictly increasing"):
        eg.write_gcsv(gyro, out)
    assert os.listdir(tmp_path) == []


def test_from_video_reads_through_telemetry_parser(db, tmp_path):
    source = tmp_path / "clip.gcsv"
    write_gcsv_input(source)
    log = db.GyroLog.fromVideo(str(source))
    options = db.GyroLogOptions()
    options.gcsvAxes = "gyroflow"
    direct = db.GyroLog.load(str(source), options)  # the same file, its YxZ read into Gyroflow's frame
    assert log.times.shape == (200,) and log.rates.shape == (200, 3)
    np.testing.assert_allclose(log.times, direct.times, rtol=0, atol=1e-12)
    np.testing.assert_allclose(log.rates, direct.rates, rtol=1e-12, atol=1e-15)
    assert log.frameReadoutTime == pytest.approx(15.23e-3, rel=1e-15)
    assert log.frameReadoutDirection == db.READOUT_TOP_TO_BOTTOM
    # Options other than the frame carry over; gcsvAxes is Gyroflow's whatever it says.
    options = db.GyroLogOptions()
    options.orientation = "yxz"  # undoes the frame's own yxz: the rates in Gyroflow's frame, as the parser gave them
    options.gcsvAxes = "camera"
    np.testing.assert_allclose(db.GyroLog.fromVideo(str(source), options).rates, camera_from_gyroflow(log.rates),
                               rtol=1e-12, atol=1e-15)
    with pytest.raises(ValueError, match="no such file"):
        db.GyroLog.fromVideo(str(tmp_path / "missing.mp4"))
    (tmp_path / "notes.txt").write_text("no telemetry in here\n")
    with pytest.raises(ValueError, match="notes.txt: telemetry-parser reads no gyro"):
        db.GyroLog.fromVideo(str(tmp_path / "notes.txt"))


def test_phone_layouts_agree_with_telemetry_parser(db, tmp_path):
    """Column order, time unit and rate unit of the two phone layouts, as telemetry-parser reads them."""
    rng = np.random.default_rng(5)
    rates = rng.normal(0, 1, size=(60, 3))
    sensor_logger = tmp_path / "Gyroscope.csv"
    t_ns = 1767620467350470700 + np.arange(60) * 5_000_123
    sensor_logger.write_text("time,seconds_elapsed,z,y,x\n" + "".join(
        f"{t},{k * 0.005:.6f},{float(w[2])!r},{float(w[1])!r},{float(w[0])!r}\n" for k, (t, w) in enumerate(zip(t_ns, rates))))
    opencamera = tmp_path / "VID_20240101_120000_gyro.csv"
    opencamera.write_text("".join(f"{float(w[0])!r},{float(w[1])!r},{float(w[2])!r},{123456789012345 + k * 4_999_877}\n"
                                  for k, w in enumerate(rates)))
    # telemetry-parser holds times as doubles: an epoch in ns (~1.8e18) keeps steps of 256 ns there, a
    # clock since boot (~1.2e14 ns) far below 1 ns. This reader keeps the nanoseconds of both: the epoch
    # counted from timeOrigin (steps exact to 1e-15 s), the clock since boot as seconds (1.5e-11 s apart).
    for path, layout, steps_ns, parser_ulp, own_ulp in (
            (sensor_logger, "sensor-logger", 5_000_123, 256e-9, 1e-15),
            (opencamera, "opencamera-sensors", 4_999_877, 3e-11, 3e-11)):
        imu = telemetry_parser.Parser(str(path)).normalized_imu()
        parsed = np.array([s["gyro"] for s in imu]) * DEG
        parsed_ms = np.array([s["timestamp_ms"] for s in imu])
        as_logged = db.GyroLogOptions()
        as_logged.orientation = "XYZ"  # the phone's axes, as telemetry-parser passes them on
        log = db.GyroLog.load(str(path), as_logged)
        assert log.layout == layout
        np.testing.assert_allclose(log.rates, parsed, rtol=1e-12, atol=1e-14)
        np.testing.assert_allclose(np.diff(log.times), np.diff(parsed_ms) * 1e-3, rtol=0, atol=parser_ulp)
        np.testing.assert_allclose(np.diff(log.times), steps_ns * 1e-9, rtol=0, atol=own_ulp)
        # By default the phone's axes (x right, y up, z out of the screen) become camera axes.
        np.testing.assert_allclose(db.GyroLog.load(str(path)).rates, rates * [1, -1, -1], rtol=1e-15)


def test_extract_gyro_command(db, tmp_path):
    source = tmp_path / "clip.gcsv"
    write_gcsv_input(source)
    out = tmp_path / "out.gcsv"

    def run(*args):
        return subprocess.run([sys.executable, "-m", "dynblur.extract_gyro", *map(str, args)], cwd=tmp_path,
                              capture_output=True, text=True, timeout=120)

    done = run(source, out)
    assert done.returncode == 0, done.stderr
    assert "200 gyro samples" in done.stdout and "frame readout 15.230 ms" in done.stdout
    options = db.GyroLogOptions()
    options.gcsvAxes = "gyroflow"
    assert db.GyroLog.load(str(out), options).times.shape == (200,)
    again = run(source, out)
    assert again.returncode == 2 and "exists; --force replaces it" in again.stderr
    assert run(source, out, "--force").returncode == 0
    (tmp_path / "notes.txt").write_text("no telemetry in here\n")
    missing = tmp_path / "from_notes.gcsv"
    refused = run(tmp_path / "notes.txt", missing)
    assert refused.returncode == 1 and "notes.txt" in refused.stderr and not missing.exists()
    usage = run("--help")
    assert usage.returncode == 0 and "gcsv" in usage.stdout and "Exit status" in usage.stdout
