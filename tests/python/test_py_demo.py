# SPDX-License-Identifier: Apache-2.0
"""samples/demo.py runs (small frame, few iterations, Agg backend) and writes its figures."""
import os
import pathlib
import subprocess
import sys

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


def test_demo_runs(db, tmp_path):
    pytest.importorskip("matplotlib")
    env = dict(os.environ, MPLBACKEND="Agg")
    cmd = [sys.executable, str(REPO / "samples" / "demo.py"), "--size", "160x120", "--iterations", "5",
           "--out", str(tmp_path)]
    done = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=300)
    print(done.stdout)
    assert done.returncode == 0, done.stderr
    assert "variant" in done.stdout and "PSNR" in done.stdout
    for name in ("panel.png", "trajectory.png"):
        assert (tmp_path / name).stat().st_size > 5000


def test_demo_help():
    done = subprocess.run([sys.executable, str(REPO / "samples" / "demo.py"), "--help"],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0 and "--out" in done.stdout
