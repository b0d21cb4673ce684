# SPDX-License-Identifier: Apache-2.0
"""samples/visual_servo.py, the Python twin of dynblur_visual_servo: it converges from 8° off within
the C++ sample's two cycles, restoration never loses the target a raw frame showed, and it writes
its outputs; on a pan-tilt head (--mount pan-tilt) likewise; --help and bad options."""
import importlib.util
import pathlib
import subprocess
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
SAMPLE = REPO / "samples" / "visual_servo.py"


def load_sample():
    spec = importlib.util.spec_from_file_location("visual_servo_sample", SAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_converges_from_eight_degrees_and_writes_its_outputs(db, tmp_path):
    pytest.importorskip("matplotlib")
    sample = load_sample()
    args = sample.parse_args(["--cycles", "3", "--out", str(tmp_path)])
    report = sample.run(args, progress=print)
    sample.write_outputs(report, tmp_path)
    cycles = report["cycles"]
    assert cycles[0]["true_px"] > 40  # 8° at fx = 300 px
    assert abs(cycles[0]["measured_px"] - cycles[0]["true_px"]) < 1.0
    within = sample.cycles_to_within(report, 1.0)
    print(f"error <= 1 px from cycle {within} on; final {report['final']}")
    assert 0 <= within <= 2
    frames, raw, restored = sample.detection_tally(report)
    print(f"windows I-III: {frames} frames, target found raw {raw}, restored {restored}")
    assert frames >= 2
    assert restored >= raw
    for f in report["frames"]:
        assert f["restored"][0] or not f["raw"][0], f"frame {f['index']}: restoration lost the target"
    for name in ("cycles.csv", "frames.csv"):
        assert len((tmp_path / name).read_text().splitlines()) > 3
    for name in ("error.png", "strip.png"):
        assert (tmp_path / name).stat().st_size > 2000


def test_pan_tilt_converges_from_eight_degrees_along_the_diagonal(db, tmp_path):
    pytest.importorskip("matplotlib")
    sample = load_sample()
    args = sample.parse_args(["--mount", "pan-tilt", "--cycles", "3", "--out", str(tmp_path)])
    report = sample.run(args, progress=print)
    sample.write_outputs(report, tmp_path)
    cycles = report["cycles"]
    assert cycles[0]["true_px"] > 40  # 8° at fx = 300 px, 5.66° on each axis
    assert abs(cycles[0]["measured_px"] - cycles[0]["true_px"]) < 1.0
    pan, tilt = (int(v) for v in cycles[0]["to_level"].split("/"))
    assert pan > 100 and tilt > 100  # both axes turned, each about 5.66° of 0.05° levels
    within = sample.cycles_to_within(report, 1.0)
    frames, raw, restored = sample.detection_tally(report)
    print(f"pan-tilt: error <= 1 px from cycle {within} on; final {report['final']}; windows I-III: {frames} frames, "
          f"target found raw {raw}, restored {restored}")
    assert 0 <= within <= 2
    assert frames >= 2
    assert restored >= raw
    for f in report["frames"]:
        assert f["restored"][0] or not f["raw"][0], f"frame {f['index']}: restoration lost the target"
    assert len((tmp_path / "cycles.csv").read_text().splitlines()) == 4


def test_help_and_bad_options():
    done = subprocess.run([sys.executable, str(SAMPLE), "--help"], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0 and "--cycles" in done.stdout and "--deadband-px" in done.stdout
    assert "--mount" in done.stdout
    for option, value in (("--cycles", "0"), ("--start-deg", "20"), ("--gain", "2"), ("--deadband-px", "-1"),
                          ("--mount", "roll")):
        done = subprocess.run([sys.executable, str(SAMPLE), option, value], capture_output=True, text=True, timeout=60)
        assert done.returncode == 2, (option, done.stderr)
        assert option in done.stderr, done.stderr
