# SPDX-License-Identifier: Apache-2.0
"""The Python API of dynblur: the README example verbatim, every bound class and function."""
import math

import numpy as np
import pytest

from conftest import make_scene


def test_readme_example_verbatim(tmp_path):
    import cv2, numpy as np  # noqa: E401
    db = cv2.dynblur
    t = np.linspace(0.0, 0.1, 201)
    fx = fy = 154.0
    cx, cy, width, height = 79.5, 59.5, 160, 120
    sharp = make_scene(height, width)
    plant = db.Plant.create(naturalFreqHz=14.4, dampingRatio=0.12, gain=np.deg2rad(1.0))
    sched = db.SwitchSchedule(times=[0.0, 0.035], levels=[6, 10], initialLevel=0)
    sched = db.SwitchPlanner.create(plant, maxLevel=16).plan(0.0, np.deg2rad(10), startTime=0.0)
    theta = plant.response(sched, t)                 # float64 array, same shape as t
    cam = db.CameraModel.create(fx, fy, cx, cy, width, height)
    shutter = db.RollingShutter(frameStart=0.005, exposure=0.008, lineDelay=62.5e-6, rows=height)
    window = db.classifyExposure(plant, sched, shutter)   # db.EXPOSURE_I .. db.EXPOSURE_IV
    blurred = db.renderBlurred(sharp, plant, sched, cam, shutter, thetaRef=np.deg2rad(10))
    deblurrer = db.DynamicDeblurrer.create(plant, cam)
    restored = deblurrer.deblur(blurred, sched, shutter)  # thetaRef defaults to the final angle
    deblurrer.setPsfModel(db.PSF_UNIFORM)                 # or db.PSF_ROWS, db.PSF_TILES

    assert theta.dtype == np.float64 and theta.shape == t.shape
    assert abs(theta[-1] - np.deg2rad(10)) < 1e-3
    assert window in (db.EXPOSURE_I, db.EXPOSURE_II, db.EXPOSURE_III, db.EXPOSURE_IV)
    assert blurred.shape == sharp.shape and blurred.dtype == np.float32
    assert restored.shape == sharp.shape and restored.dtype == np.float32
    assert deblurrer.getPsfModel() == db.PSF_UNIFORM
    err_blurred = np.mean(np.abs(blurred - sharp)[10:-10, 10:-10])
    err_restored = np.mean(np.abs(restored - sharp)[10:-10, 10:-10])
    print(f"window {window}: mean |error| blurred {err_blurred:.4f}, restored {err_restored:.4f}")
    assert err_restored < err_blurred


def test_cv2_dynblur_is_the_dynblur_module():
    import cv2
    import dynblur
    assert cv2.dynblur is dynblur
    assert issubclass(dynblur.error, cv2.error)


def test_schedule_fields_and_io(db, tmp_path):
    s = db.SwitchSchedule(times=[0.0, 0.01, 0.02], levels=[4, -2, 3], initialLevel=1)
    assert s.times == [0.0, 0.01, 0.02] and s.levels == [4, -2, 3] and s.initialLevel == 1
    assert s.finalLevel() == 3
    assert s.levelAt(-1.0) == 1 and s.levelAt(0.005) == 4 and s.levelAt(0.015) == -2 and s.levelAt(1.0) == 3
    assert math.isnan(s.settleTime) and math.isnan(s.peakVelocity)
    s.validate()
    with pytest.raises(db.error, match="level"):
        s.validate(maxLevel=3)
    s.times = [0.0, 0.02, 0.03]
    assert s.times == [0.0, 0.02, 0.03]
    for ext in ("yml", "json"):
        path = str(tmp_path / f"s.{ext}")
        s.save(path)
        back = db.SwitchSchedule.load(path)
        assert back.times == s.times and back.levels == s.levels and back.initialLevel == 1
    assert "SwitchSchedule(times=" in repr(s)
    assert db.SwitchSchedule().levels == []


def test_plant_getters_velocity_and_identify(db):
    plant = db.Plant.create(naturalFreqHz=12.0, dampingRatio=0.1, gain=0.02)
    assert plant.getNaturalFreqHz() == pytest.approx(12.0)
    assert plant.getDampingRatio() == pytest.approx(0.1)
    assert plant.getGain() == pytest.approx(0.02)
    assert plant.restingAngle(5) == pytest.approx(0.1)
    sched = db.SwitchSchedule(times=[0.01], levels=[5])
    t = np.linspace(0, 0.4, 2001)
    theta, omega = plant.response(sched, t), plant.velocity(sched, t)
    away = np.abs(t - 0.01) > 1e-3  # the finite difference straddles the step's acceleration jump
    np.testing.assert_allclose(np.gradient(theta, t)[away], omega[away], atol=2e-3 * np.max(np.abs(omega)))
    # any shape in, same shape out; lists are accepted
    assert plant.response(sched, t[:2000].reshape(40, 50)).shape == (40, 50)
    assert plant.response(sched, [0.0, 0.5]).shape == (2,)
    fitted, rms, delay = db.Plant.identify(t, theta, sched)
    assert fitted.getNaturalFreqHz() == pytest.approx(12.0, rel=1e-4)
    assert fitted.getDampingRatio() == pytest.approx(0.1, rel=1e-3)
    assert rms < 1e-6 and delay == 0.0
    fitted, rms, delay = db.Plant.identify(t, plant.response(sched, t - 0.004), sched, estimateDelay=True)
    assert delay == pytest.approx(0.004, abs=2e-4)


def test_ode_plants_agree_with_closed_form(db):
    plant = db.Plant.create(14.4, 0.12, np.deg2rad(1))
    sched = db.SwitchPlanner.create(plant, 16).plan(0.0, np.deg2rad(8))
    t = np.linspace(-0.01, 0.1, 300)
    ref = plant.response(sched, t)
    linear = db.OdePlant.createLinear(14.4, 0.12, np.deg2rad(1))
    assert isinstance(linear, db.Plant)
    np.testing.assert_allclose(linear.response(sched, t), ref, atol=1e-6)

    wn, z, g = 2 * np.pi * 14.4, 0.12, np.deg2rad(1)
    calls = []

    def rhs(time, x, u):
        calls.append(time)
        return [x[1], wn * wn * (g * u - x[0]) - 2 * z * wn * x[1]]

    custom = db.OdePlant.create(rhs, 2, lambda level: [g * level, 0.0], 14.4, 0.12, g)
    np.testing.assert_allclose(custom.response(sched, t), ref, atol=1e-6)
    assert len(calls) > 10

    def broken(time, x, u):
        raise RuntimeError("rhs failed on purpose")

    bad = db.OdePlant.create(broken, 2, lambda level: [0.0, 0.0], 14.4, 0.12, g)
    with pytest.raises(RuntimeError, match="on purpose"):
        bad.response(sched, t)


def test_planner_and_residual_vibration(db):
    plant = db.Plant.create()
    planner = db.SwitchPlanner.create(plant, maxLevel=16, mode=db.PLAN_ROBUST, minDwell=0.002)
    assert planner.getMode() == db.PLAN_ROBUST and planner.getMaxLevel() == 16
    planner.setMode(db.PLAN_FAST)
    planner.setMinDwell(0.003)
    planner.setSettleBand(0.05)
    planner.setRobustRange(0.05)
    planner.setRobustTolerance(0.03)
    planner.setMaxLevel(12)
    assert (planner.getMode(), planner.getMaxLevel()) == (db.PLAN_FAST, 12)
    assert planner.getMinDwell() == pytest.approx(0.003) and planner.getSettleBand() == pytest.approx(0.05)
    assert planner.getRobustRange() == pytest.approx(0.05) and planner.getRobustTolerance() == pytest.approx(0.03)
    assert planner.getPlant().getNaturalFreqHz() == pytest.approx(14.4)
    s = planner.plan(0.0, np.deg2rad(10), startTime=0.1)
    assert s.times[0] == pytest.approx(0.1) and s.finalLevel() == 10
    assert np.all(np.diff(s.times) >= 0.003 - 1e-12)
    assert s.residualVibration < 1e-6
    assert db.residualVibration(s, 14.4, 0.12) < 1e-6
    assert db.residualVibration(db.SwitchSchedule([0.0], [4]), 14.4, 0.12) > 0.5
    assert s.peakVelocity > 1.0 and 0 < s.settleTime < 0.1


def test_shutter_and_exposure_windows(db):
    sh = db.RollingShutter(frameStart=0.01, exposure=0.008, lineDelay=1e-4, rows=100)
    assert sh.rowInterval(10) == pytest.approx((0.011, 0.019))
    assert sh.intervalAt(10.5) == pytest.approx((0.01105, 0.01905))
    assert sh.readoutInterval() == pytest.approx((0.01, 0.01 + 99e-4 + 0.008))
    sh.validate()
    sh.rows = 0
    with pytest.raises(db.error, match="rows"):
        sh.validate()
    plant = db.Plant.create()
    sched = db.SwitchPlanner.create(plant).plan(0.0, np.deg2rad(10))
    assert db.classifyExposure(plant, sched, db.RollingShutter(-0.1, 0.008, 0.0, 10)) == db.EXPOSURE_IV
    assert db.classifyExposure(plant, sched, db.RollingShutter(0.002, 0.008, 1e-4, 300)) == db.EXPOSURE_III
    assert db.classifyExposure(plant, sched, db.RollingShutter(-0.004, 0.008, 0.0, 10)) == db.EXPOSURE_I
    assert db.classifyExposure(plant, sched, db.RollingShutter(0.002, 0.005, 0.0, 10)) == db.EXPOSURE_II
    assert db.classifyExposure(plant, db.SwitchSchedule(), db.RollingShutter()) == db.EXPOSURE_IV


def test_camera_model(db, tmp_path):
    cam = db.CameraModel.create(600.0, 610.0, 320.0, 240.0, 640, 480, kud=0.01, kdu=-0.01)
    assert (cam.getFx(), cam.getFy(), cam.getCx(), cam.getCy()) == (600.0, 610.0, 320.0, 240.0)
    assert (cam.getKud(), cam.getKdu()) == (0.01, -0.01)
    assert cam.getImageSize() == (640, 480)
    np.testing.assert_allclose(cam.cameraMatrix(), [[600, 0, 320], [0, 610, 240], [0, 0, 1]])
    assert cam.getMountAxis() == pytest.approx((1.0, 0.0, 0.0))
    path = str(tmp_path / "cam.xml")
    cam.save(path, cameraName="c")
    back = db.CameraModel.load(path, cameraName="c")
    assert back.getFx() == pytest.approx(600.0) and back.getKud() == pytest.approx(0.01)
    assert cam.pixelToNormalized((320.0, 240.0)) == pytest.approx((0.0, 0.0))
    assert cam.normalizedToPixel((0.0, 0.0)) == pytest.approx((320.0, 240.0))
    pts = np.array([[320.0, 240.0], [100.0, 50.0], [600.0, 400.0]])
    np.testing.assert_allclose(cam.viewToReference(pts, 0.0), pts, atol=1e-9)
    moved = cam.viewToReference(pts, np.deg2rad(1.0))
    assert moved.shape == (3, 2) and np.all(np.abs(moved[:, 1] - pts[:, 1]) > 5)
    assert cam.viewToReference([320.0, 240.0], 0.01).shape == (2,)
    cam.setMountAxis((0, 2.0, 0))
    assert cam.getMountAxis() == pytest.approx((0.0, 1.0, 0.0))


def test_render_noise_and_srgb(db, small_setup):
    plant, sched, cam, shutter = small_setup
    sharp = make_scene(120, 160)
    blurred = db.renderBlurred(sharp, plant, sched, cam, shutter)
    assert blurred.shape == (120, 160, 3) and blurred.dtype == np.float32
    assert np.mean(np.abs(blurred - sharp)) > 0.01
    noisy = db.addSensorNoise(blurred, fullWellElectrons=4000, seed=7)
    np.testing.assert_array_equal(noisy, db.addSensorNoise(blurred, fullWellElectrons=4000, seed=7))
    assert 0.001 < np.std(noisy - blurred) < 0.05
    s8 = db.linearToSrgb(sharp)
    assert s8.dtype == np.uint8
    np.testing.assert_allclose(db.srgbToLinear(s8), sharp, atol=0.01)
    assert db.linearToSrgb(sharp, depth=5).dtype == np.float32
    rendered8 = db.renderBlurred(s8, plant, sched, cam, shutter)
    assert rendered8.dtype == np.uint8 and rendered8.shape == s8.shape


def test_psf_bank_and_deconvolution(db, small_setup):
    plant, sched, cam, shutter = small_setup
    gen = db.PsfGenerator.create(plant, cam)
    gen.setBandRows(4)
    gen.setTileGrid((4, 3))
    gen.setMaxKernelSize(301)
    assert gen.getBandRows() == 4 and gen.getTileGrid() == (4, 3) and gen.getMaxKernelSize() == 301
    sharp = make_scene(120, 160)
    blurred = db.renderBlurred(sharp, plant, sched, cam, shutter)
    for model in (db.PSF_UNIFORM, db.PSF_ROWS, db.PSF_TILES):
        bank = gen.generate(model, sched, shutter)
        bank.validate()
        assert bank.model == model and bank.imageSize == (160, 120)
        assert len(bank.kernels) == len(bank.nodeRows) * len(bank.nodeCols) == len(bank.shifts)
        assert all(k.dtype == np.float32 and abs(k.sum() - 1) < 1e-4 for k in bank.kernels)
        assert not bank.isIdentity()
        w, h = bank.maxKernelSize()
        assert w >= 1 and h >= 1
    latent, mask = db.richardsonLucyVariant(blurred, bank, db.RLParams(iterations=10), returnMask=True)
    assert latent.shape == blurred.shape and mask.dtype == np.uint8 and mask.shape == (120, 160)
    assert db.richardsonLucyVariant(blurred, bank, params=db.RLParams(iterations=2)).shape == blurred.shape
    assert db.richardsonLucyVariant(blurred, bank, db.RLParams(iterations=4, colorIterations=1)).shape == blurred.shape
    with pytest.raises(db.error, match="colorIterations"):
        db.richardsonLucyVariant(blurred, bank, db.RLParams(colorIterations=-2))
    # bfloat16 blurs: the same restoration within bfloat16's rounding; other values refused by name
    inner = (slice(10, -10), slice(10, -10))
    exact = db.richardsonLucyVariant(blurred, bank, db.RLParams(iterations=10))
    fast = db.richardsonLucyVariant(blurred, bank, db.RLParams(iterations=10, blurPrecision=db.RL_BLUR_BFLOAT16))
    assert fast.shape == exact.shape and fast.dtype == np.float32
    assert 0 < np.max(np.abs(fast - exact)[inner]) < 0.05 * np.max(exact)
    with pytest.raises(db.error, match="params.blurPrecision"):
        db.richardsonLucyVariant(blurred, bank, db.RLParams(blurPrecision=2))
    reblurred = db.applyPsfBank(sharp, bank)
    assert np.mean(np.abs(reblurred - blurred)[inner]) < 0.5 * np.mean(np.abs(sharp - blurred)[inner])
    wiener = db.wienerDeconvolve(blurred, bank, noiseToSignal=1e-2)
    assert wiener.shape == blurred.shape
    # a hand-made bank: one kernel, the identity
    ident = db.PsfBank()
    ident.model, ident.imageSize = db.PSF_UNIFORM, (160, 120)
    ident.nodeRows, ident.nodeCols = [59.5], [79.5]
    ident.kernels, ident.shifts = [np.ones((1, 1), np.float32)], [(0, 0)]
    ident.validate()
    assert ident.isIdentity()
    np.testing.assert_allclose(db.applyPsfBank(sharp, ident), sharp, atol=1e-6)


def test_rlparams(db):
    p = db.RLParams()
    assert p.iterations == 20 and p.boundary == db.RL_BOUNDARY_PAD and p.accelerate is True
    q = db.RLParams(iterations=5, damping=0.01, tvWeight=0.0, boundary=db.RL_BOUNDARY_ZERO, accelerate=False,
                    tolerance=1e-4)
    assert (q.iterations, q.damping, q.boundary, q.accelerate, q.tolerance) == (5, 0.01, 0, False, 1e-4)
    assert "RLParams(iterations=5" in repr(q)
    assert p.colorIterations == -1 and db.RLParams(colorIterations=3).colorIterations == 3
    assert p.blurPrecision == db.RL_BLUR_FLOAT32 != db.RL_BLUR_BFLOAT16
    assert db.RLParams(blurPrecision=db.RL_BLUR_BFLOAT16).blurPrecision == db.RL_BLUR_BFLOAT16
    assert "blurPrecision=1" in repr(db.RLParams(blurPrecision=1))


def test_deblurrer(db, small_setup):
    plant, sched, cam, shutter = small_setup
    sharp = make_scene(120, 160)
    blurred = db.renderBlurred(sharp, plant, sched, cam, shutter)
    deb = db.DynamicDeblurrer.create(plant, cam)
    assert deb.getPsfModel() == db.PSF_AUTO and deb.getMethod() == db.DEBLUR_RICHARDSON_LUCY
    assert deb.getLastExposureWindow() == 0
    assert math.isnan(deb.getRLParams().damping)
    restored, mask = deb.deblur(blurred, sched, shutter, returnMask=True)
    assert deb.getLastExposureWindow() == db.EXPOSURE_III
    assert len(deb.getLastPsfBank().kernels) > 1
    assert mask.dtype == np.uint8 and mask.shape == (120, 160) and mask.mean() > 100
    inner = (slice(10, -10), slice(10, -10))
    assert np.mean(np.abs(restored - sharp)[inner]) < 0.7 * np.mean(np.abs(blurred - sharp)[inner])
    deb.setMethod(db.DEBLUR_WIENER)
    assert deb.deblur(blurred, sched, shutter).shape == blurred.shape
    deb.setRLParams(db.RLParams(iterations=3))
    assert deb.getRLParams().iterations == 3
    assert deb.getPsfGenerator() is not None
    # window IV: unchanged, and not the caller's buffer
    still = db.RollingShutter(frameStart=1.0, exposure=0.008, lineDelay=shutter.lineDelay, rows=120)
    out = deb.deblur(blurred, sched, still)
    np.testing.assert_array_equal(out, blurred)
    assert not np.shares_memory(out, blurred)


def test_deblurrer_sharp_threshold(db, small_setup):
    """A frame at the very end of the move is not deconvolved under the default threshold (1 px):
    reported as sharp, no kernels; with 0 every moving frame is; the threshold is checked."""
    plant, sched, cam, shutter = small_setup
    start = shutter.frameStart
    while db.classifyExposure(plant, sched, db.RollingShutter(frameStart=start + 1e-3, exposure=0.008,
                                                              lineDelay=shutter.lineDelay, rows=120)) != db.EXPOSURE_IV:
        start += 1e-3
    last = db.RollingShutter(frameStart=start, exposure=0.008, lineDelay=shutter.lineDelay, rows=120)
    frame = db.renderBlurred(make_scene(120, 160), plant, sched, cam, last)
    deb = db.DynamicDeblurrer.create(plant, cam)
    assert deb.getSharpThreshold() == 1.0
    out = deb.deblur(frame, sched, last)
    c = deb.getLastCorrection()
    assert c.applied and c.reason.startswith("sharp: blur "), c.reason
    assert len(deb.getLastPsfBank().kernels) == 0 and out.shape == frame.shape
    deb.setSharpThreshold(0.0)
    assert deb.getSharpThreshold() == 0.0
    deb.deblur(frame, sched, last)
    assert not deb.getLastCorrection().reason.startswith("sharp") and len(deb.getLastPsfBank().kernels) > 0
    for bad in (-1.0, float("nan"), float("inf")):
        with pytest.raises(db.error, match="px = .* must be finite and >= 0"):
            deb.setSharpThreshold(bad)


def test_deblurrer_plan_and_preset(db, small_setup):
    plant, sched, cam, shutter = small_setup
    blurred = db.renderBlurred(make_scene(120, 160), plant, sched, cam, shutter)
    deb = db.DynamicDeblurrer.create(plant, cam)
    deb.deblur(blurred, sched, shutter)
    plan = deb.getLastPlan()
    assert plan.model in (db.PSF_UNIFORM, db.PSF_ROWS, db.PSF_TILES) and plan.rows == 120
    assert plan.bandStart[0] == 0 and len(plan.bandModel) == len(plan.bandStart) == len(plan.rowsError)
    shares = [plan.rowShare(m) for m in (db.PSF_UNIFORM, db.PSF_ROWS, db.PSF_TILES)]
    assert abs(sum(shares) - 1) < 1e-12
    motion = db.CameraMotion.fromPlant(plant, sched)
    assert deb.getPsfGenerator().plan(motion, shutter).bandModel == plan.bandModel
    with pytest.raises(db.error):
        deb.getPsfGenerator().setAutoTolerance(float("nan"))
    with pytest.raises(db.error):
        deb.setPreset(7)
    deb.setPreset(db.DEBLUR_PRESET_FRAME_RATE)
    assert deb.getRLParams().blurPrecision == db.RL_BLUR_BFLOAT16 and deb.getRLParams().tolerance > 0
    assert deb.deblur(blurred, sched, shutter).shape == blurred.shape


def test_deblurrer_color_at_half_resolution(db, small_setup):
    plant, sched, cam, shutter = small_setup
    # Detail in the luminance, color that varies smoothly (as in natural images)
    y, x = np.mgrid[0:120, 0:160].astype(np.float32)
    tint = np.dstack([0.6 + 0.4 * x / 160, 0.6 + 0.4 * y / 120, 1.0 - 0.4 * x / 160])
    sharp = (make_scene(120, 160, channels=1, seed=1)[..., None] * tint).astype(np.float32)
    blurred = db.renderBlurred(sharp, plant, sched, cam, shutter)
    deb = db.DynamicDeblurrer.create(plant, cam)
    assert deb.getColorResolution() == db.DEBLUR_COLOR_FULL_RESOLUTION
    deb.setRLParams(db.RLParams(iterations=6, damping=float("nan"), colorIterations=2))
    full = deb.deblur(blurred, sched, shutter)
    deb.setColorResolution(db.DEBLUR_COLOR_HALF_RESOLUTION)
    assert deb.getColorResolution() == db.DEBLUR_COLOR_HALF_RESOLUTION
    half = deb.deblur(blurred, sched, shutter)
    assert half.shape == blurred.shape and half.dtype == np.float32
    assert 0.0 <= half.min() and half.max() <= 1.0
    # the color phase ran at half resolution, and both restore the frame alike
    assert np.abs(half - full).max() > 1e-3
    inner = (slice(10, -10), slice(10, -10))
    error = {name: np.mean(np.abs(image - sharp)[inner]) for name, image in
             (("blurred", blurred), ("full", full), ("half", half))}
    assert error["half"] < 0.7 * error["blurred"] and error["half"] < 1.1 * error["full"], error
    with pytest.raises(db.error, match="resolution = 2 must be"):
        deb.setColorResolution(2)
    odd = db.DynamicDeblurrer.create(plant, db.CameraModel.create(300.0, 300.0, 80.0, 59.5, 161, 120))
    with pytest.raises(db.error, match="even image size; the camera's is 161x120"):
        odd.setColorResolution(db.DEBLUR_COLOR_HALF_RESOLUTION)


def test_errors_name_the_problem(db, small_setup):
    import cv2
    plant, sched, cam, shutter = small_setup
    with pytest.raises(cv2.error, match="times"):
        db.SwitchSchedule(times=[0.0, 0.0], levels=[1, 2]).validate()
    with pytest.raises(db.error) as info:
        db.Plant.create(naturalFreqHz=-1.0)
    assert info.value.code < 0 and "naturalFreqHz" in str(info.value)
    with pytest.raises(cv2.error):
        db.renderBlurred(make_scene(50, 60), plant, sched, cam, shutter)  # wrong size
    with pytest.raises(ValueError, match="'sharp'"):
        db.renderBlurred(np.zeros((120, 160, 5), np.float32), plant, sched, cam, shutter)
    with pytest.raises(ValueError, match="'frame'.*dtype"):
        db.DynamicDeblurrer.create(plant, cam).deblur(np.zeros((120, 160), np.int64), sched, shutter)
    with pytest.raises(ValueError, match="'blurred'.*object"):
        db.richardsonLucy(np.array([[1, "a"]], dtype=object), np.ones((1, 1), np.float32))
    with pytest.raises(ValueError, match="'psf'.*dimensions"):
        db.richardsonLucy(np.ones((8, 8), np.float32), np.ones((1, 1, 1, 1), np.float32))
    with pytest.raises(ValueError, match="'plant' is None"):
        db.classifyExposure(None, sched, shutter)
    with pytest.raises(TypeError):
        db.Plant.create(naturalFreqHz="fast")


def test_type_stub_matches_the_module(db):
    """Every name of the package's .pyi stub exists in the module and every public name of the
    module (and of each class) is in the stub, so a binding added without its stub fails."""
    import ast
    import pathlib
    stub = pathlib.Path(__file__).resolve().parents[2] / "python" / "dynblur" / "__init__.pyi"
    tree = ast.parse(stub.read_text())
    stubbed, members = set(), {}
    for node in tree.body:
        if isinstance(node, ast.ClassDef):
            stubbed.add(node.name)
            members[node.name] = {item.name if isinstance(item, (ast.FunctionDef, ast.ClassDef)) else item.target.id
                                  for item in node.body if isinstance(item, (ast.FunctionDef, ast.ClassDef, ast.AnnAssign))}
            for base in node.bases:  # a stub class lists its own members; its bases' come before it
                if isinstance(base, ast.Name) and base.id in members:
                    members[node.name] |= members[base.id]
        elif isinstance(node, ast.FunctionDef):
            stubbed.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            stubbed.add(node.target.id)
    public = {name for name in dir(db) if not name.startswith("_") and not isinstance(getattr(db, name), type(ast))}
    assert stubbed - {"__version__", "__opencv_version__"} - public == set(), "in the stub, not in the module"
    assert public - stubbed == set(), "in the module, not in the stub"
    for name, names in members.items():
        cls = getattr(db, name)
        if not isinstance(cls, type) or issubclass(cls, Exception):
            continue
        bound = {n for n in dir(cls) if not n.startswith("_")}
        assert names - {"__init__"} - bound == set(), f"{name}: in the stub, not bound"
        assert bound - names == set(), f"{name}: bound, not in the stub"
