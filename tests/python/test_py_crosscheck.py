# SPDX-License-Identifier: Apache-2.0
"""Cross-checks of the bindings against scipy and scikit-image.

Plant.response vs scipy.signal.lsim (zero-order hold, exact for a staircase on the sample grid),
and uniform richardsonLucy vs skimage.restoration.richardson_lucy (RL_BOUNDARY_ZERO, constant 0.5
start, no damping/TV/acceleration: the semantics test_rl_skimage.py validates through the CLI).
"""
import numpy as np
import pytest
from scipy import signal


def lsim_response(fn_hz, zeta, gain, sched, t):
    wn = 2 * np.pi * fn_hz
    sys = signal.StateSpace([[0, 1], [-wn * wn, -2 * zeta * wn]], [[0], [wn * wn * gain]], [[1, 0]], [[0]])
    u = np.array([sched.levelAt(float(x)) for x in t], dtype=float)
    _, y, _ = signal.lsim(sys, u, t - t[0], X0=[gain * sched.initialLevel, 0.0], interp=False)
    return y


@pytest.mark.parametrize("initial", [0, 3])
def test_plant_response_matches_scipy_lsim(db, initial):
    dt = 1e-4
    t = np.arange(0, 3000) * dt - 0.01
    plant = db.Plant.create(naturalFreqHz=14.4, dampingRatio=0.12, gain=np.deg2rad(1.0))
    planned = db.SwitchPlanner.create(plant, maxLevel=16).plan(np.deg2rad(initial), np.deg2rad(10), startTime=0.0)
    # switching instants moved onto the sample grid, where zero-order hold is exact
    on_grid = [float(t[int(round((x - t[0]) / dt))]) for x in planned.times]
    sched = db.SwitchSchedule(times=on_grid, levels=planned.levels, initialLevel=planned.initialLevel)
    for s in (sched, db.SwitchSchedule(times=[t[100], t[450]], levels=[6, 10], initialLevel=initial)):
        got = plant.response(s, t)
        ref = lsim_response(14.4, 0.12, np.deg2rad(1.0), s, t)
        err = np.max(np.abs(got - ref))
        print(f"[ measured ] max |Plant.response - scipy lsim| = {err:.2e} rad")
        assert err < 1e-6


def make_image(shape, seed):
    from scipy.ndimage import gaussian_filter
    rng = np.random.default_rng(seed)
    image = gaussian_filter(rng.random(shape), 2.0)
    image = (image - image.min()) / (image.max() - image.min())
    return (0.05 + 0.9 * image).astype(np.float32)


def motion_psf(rows, cols, seed):
    rng = np.random.default_rng(seed)
    psf = np.zeros((rows, cols), np.float32)
    for t in np.linspace(0, 1, 60):
        y = int(round((rows - 1) * (0.5 + 0.4 * np.sin(2.5 * t) - 0.2)))
        psf[min(max(y, 0), rows - 1), int(round((cols - 1) * t))] += 1
    psf += 0.01 * rng.random(psf.shape, dtype=np.float32)
    return (psf / psf.sum()).astype(np.float32)


@pytest.mark.parametrize("shape,psf_shape", [((64, 80), (7, 15)), ((97, 51), (9, 5))])
def test_uniform_rl_matches_skimage(db, shape, psf_shape):
    from scipy.signal import convolve
    from skimage.restoration import richardson_lucy
    latent = make_image(shape, 1)
    psf = motion_psf(*psf_shape, seed=2)
    blurred = convolve(latent, psf, mode="same").astype(np.float32)
    blurred = np.clip(blurred + np.random.default_rng(3).normal(0, 0.003, shape), 0, None).astype(np.float32)
    expected = richardson_lucy(blurred, psf, num_iter=10, clip=False)
    params = db.RLParams(iterations=10, damping=0.0, tvWeight=0.0, boundary=db.RL_BOUNDARY_ZERO,
                         accelerate=False, tolerance=0.0)
    got = db.richardsonLucy(blurred, psf, params, initial=np.full(shape, 0.5, np.float32))
    err = np.max(np.abs(got - expected))
    print(f"[ measured ] max |richardsonLucy - skimage richardson_lucy| = {err:.2e}")
    assert got.dtype == np.float32 and got.shape == shape
    assert np.max(np.abs(expected - 0.5)) > 0.1
    assert err < 1e-5
    flipped = db.richardsonLucy(blurred, psf[::-1, ::-1], params, initial=np.full(shape, 0.5, np.float32))
    assert np.max(np.abs(flipped - expected)) > 1e-2  # the comparison can fail
