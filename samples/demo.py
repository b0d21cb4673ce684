#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""dynblur demo in Python: a small version of samples/demo.cpp drawn with matplotlib.

Plans a 10° saccade on the seed's positioner (14.4 Hz, ζ = 0.12, 1°/level, 16 levels), renders
with the physical forward model what a rolling-shutter webcam records in exposure window III
(sensor noise included), restores it with the seed's uniform PSF and with the spatially variant
pipeline (PSF tiles), prints a PSNR table against the truth and writes two figures:

  <out>/panel.png       blurred | uniform | spatially variant | truth
  <out>/trajectory.png  θ(t) with the exposure interval of every 40th row

Needs the dynblur package (pip install . at the repository root) and matplotlib.
"""
import argparse
import os
import pathlib
import time

import numpy as np


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", default="demo_out_py", help="folder for the figures (default: %(default)s)")
    p.add_argument("--size", default="640x480", help="frame size WxH, pixels (default: %(default)s)")
    p.add_argument("--iterations", type=int, default=20, help="Richardson–Lucy iterations (default: %(default)s)")
    p.add_argument("--scene", default=None, help="image file to use as the scene (default: a generated one)")
    p.add_argument("--seed", type=int, default=1, help="noise and scene seed (default: %(default)s)")
    return p.parse_args(argv)


def generated_scene(height, width, seed):
    """Linear-intensity RGB scene: bars, a checkerboard corner, disks and fine text-like strokes."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:height, 0:width].astype(np.float32)
    img = 0.35 + 0.25 * np.sin(x / (width / 9.0)) * np.cos(y / (height / 5.0))
    img += 0.2 * ((np.floor(x / 16) + np.floor(y / 16)) % 2) * (x < width / 3) * (y < height / 2)
    for _ in range(25):
        cy, cx, r = rng.uniform(0, height), rng.uniform(0, width), rng.uniform(3, height / 10)
        img = np.where((y - cy) ** 2 + (x - cx) ** 2 < r * r, rng.uniform(0.05, 0.95), img)
    img += 0.3 * ((x.astype(int) % 9 < 2) & (np.abs(y - 0.75 * height) < height / 12))
    img = np.clip(img, 0.02, 0.98).astype(np.float32)
    tint = np.stack([img, np.clip(img * 0.9 + 0.05, 0, 1), np.clip(1.0 - 0.8 * img, 0, 1)], axis=-1)
    return tint.astype(np.float32)


def load_scene(path, width, height, db):
    import cv2
    img = cv2.imread(path, cv2.IMREAD_COLOR)
    if img is None:
        raise SystemExit(f"cannot read {path}")
    img = cv2.resize(img, (width, height), interpolation=cv2.INTER_AREA)[..., ::-1]
    return db.srgbToLinear(np.ascontiguousarray(img))


def psnr(a, b, mask):
    err = np.mean((a[mask] - b[mask]) ** 2)
    return 10 * np.log10(1.0 / max(err, 1e-12))


def main(argv=None):
    args = parse_args(argv)
    import matplotlib
    if not os.environ.get("MPLBACKEND"):
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import dynblur as db

    width, height = (int(v) for v in args.size.lower().split("x"))
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    # 1. The positioner and a 10° move.
    plant = db.Plant.create(naturalFreqHz=14.4, dampingRatio=0.12, gain=np.deg2rad(1.0))
    planner = db.SwitchPlanner.create(plant, maxLevel=16, mode=db.PLAN_ROBUST)
    sched = planner.plan(0.0, np.deg2rad(10.0), startTime=0.0)
    print(f"plan: times {np.round(sched.times, 4).tolist()} s, levels {sched.levels}, "
          f"settle {1e3 * sched.settleTime:.1f} ms, peak {np.rad2deg(sched.peakVelocity):.0f} °/s")

    # 2. A C270-like webcam scaled to the frame size: 30 fps rolling readout, 8 ms exposure.
    fx = 1230.0 * width / 1280.0
    cam = db.CameraModel.create(fx, fx, (width - 1) / 2, (height - 1) / 2, width, height)
    line_delay, exposure = 0.030 / height, 0.008
    starts = [s for s in np.arange(-0.05, 0.1, 0.0005)
              if db.classifyExposure(plant, sched, db.RollingShutter(s, exposure, line_delay, height)) == db.EXPOSURE_III]
    frame_start = float(starts[len(starts) // 2])  # the middle of window III's run
    shutter = db.RollingShutter(frameStart=frame_start, exposure=exposure, lineDelay=line_delay, rows=height)

    # 3. What the camera records.
    truth = load_scene(args.scene, width, height, db) if args.scene else generated_scene(height, width, args.seed)
    t0 = time.perf_counter()
    blurred = db.addSensorNoise(db.renderBlurred(truth, plant, sched, cam, shutter), seed=args.seed)
    t_render = time.perf_counter() - t0

    # 4. Restorations: the seed's uniform PSF, then the spatially variant pipeline.
    deblurrer = db.DynamicDeblurrer.create(plant, cam)
    params = deblurrer.getRLParams()
    params.iterations = args.iterations
    deblurrer.setRLParams(params)
    results = {}
    for name, model in (("uniform", db.PSF_UNIFORM), ("variant", db.PSF_TILES)):
        deblurrer.setPsfModel(model)
        t0 = time.perf_counter()
        restored, valid = deblurrer.deblur(blurred, sched, shutter, returnMask=True)
        results[name] = (restored, valid, time.perf_counter() - t0)

    # 5. PSNR where the variant restoration is valid, away from the frame's edge.
    mask = results["variant"][1] > 0
    margin = max(4, height // 40)
    mask[:margin], mask[-margin:], mask[:, :margin], mask[:, -margin:] = False, False, False, False
    mask = np.repeat(mask[..., None], 3, axis=2)
    print(f"frame start {1e3 * frame_start:.1f} ms (window III), render {1e3 * t_render:.0f} ms")
    print(f"{'frame':<10}{'PSNR dB':>10}{'time ms':>10}")
    print(f"{'blurred':<10}{psnr(blurred, truth, mask):>10.2f}{'':>10}")
    for name, (restored, _, dt) in results.items():
        print(f"{name:<10}{psnr(restored, truth, mask):>10.2f}{1e3 * dt:>10.0f}")

    # 6. Figures.
    def show(img):
        return db.linearToSrgb(np.clip(img, 0, 1).astype(np.float32))

    fig, axes = plt.subplots(1, 4, figsize=(16, 4.4))
    panels = [("blurred", blurred), ("uniform PSF", results["uniform"][0]),
              ("spatially variant", results["variant"][0]), ("truth", truth)]
    for ax, (title, img) in zip(axes, panels):
        ax.imshow(show(img))
        label = title if title == "truth" else f"{title}\n{psnr(img, truth, mask):.2f} dB"
        ax.set_title(label)
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(out / "panel.png", dpi=100, bbox_inches="tight")  # two-line titles stay whole
    plt.close(fig)

    t = np.linspace(-0.01, 0.08, 2000)
    theta = np.rad2deg(plant.response(sched, t))
    fig, ax = plt.subplots(figsize=(9, 4.5))
    ax.plot(1e3 * t, theta, color="k", label="θ(t)")
    for r in range(0, height, 40):
        a, b = shutter.rowInterval(r)
        ax.plot([1e3 * a, 1e3 * b], [r / height * 11, r / height * 11], color="tab:blue", lw=3,
                label="row exposure (height ∝ row)" if r == 0 else None)
    for ts in sched.times:
        ax.axvline(1e3 * ts, color="tab:red", lw=0.6, ls="--")
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("θ (°)")
    ax.set_title("10° saccade and the frame's row exposure intervals (window III)")
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(out / "trajectory.png", dpi=100, bbox_inches="tight")
    plt.close(fig)
    print(f"wrote {out / 'panel.png'} and {out / 'trajectory.png'}")


if __name__ == "__main__":
    main()
