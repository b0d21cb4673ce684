#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""dynblur visual servoing in Python: the twin of dynblur_visual_servo (samples/visual_servo.cpp).

A camera on the tilt positioner looks at a textured plane carrying a target, a column of three
AprilTags 36h11 (ids 0-2), that starts --start-deg off the image centre. Each cycle:

  detect the target in the latest RESTORED frame (cv2.aruco, AprilTag 36h11)
  -> the tilt that centres it (exact for a pure rotation; the C++ sample asks ViSP's vpServo, which
     Python lacks, and with gain 1 the two agree to second order)
  -> SwitchPlanner: an integer-level saccade without residual vibration, on the plant
  -> the rolling-shutter camera keeps taking frames while the mechanism moves: each is rendered with
     renderBlurred + addSensorNoise, classified (windows I-IV), restored with DynamicDeblurrer
     (PSF_ROWS) and searched for the target raw and restored.

With --mount pan-tilt the camera sits on a pan (0, 1, 0) carrying a tilt (1, 0, 0), each axis that
positioner, and the target starts --start-deg off along the diagonal (as dynblur_visual_servo --mount
pan-tilt --scenario step): the pan and tilt that centre it come from Mount.anglesFor, MountPlanner
moves both axes together and every frame is rendered, classified and restored from the mount's
CameraMotion.

The camera, plant and target are the C++ sample's defaults (320x240, fx = 300 px, 30 fps, 33 ms
exposure; 14.4 Hz, zeta = 0.12, 0.05 deg/level, 400 levels; 0.75 px dead band). Writes
<out>/cycles.csv, frames.csv, error.png (error per cycle) and strip.png (raw | restored frames
taken while moving, detections drawn).

Needs the dynblur package (pip install . at the repository root), opencv-python and matplotlib.
"""
import argparse
import csv
import math
import pathlib
import sys
import time

import numpy as np

WINDOW_NAMES = {1: "I", 2: "II", 3: "III", 4: "IV"}
TAG_IDS = 3


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--cycles", type=int, default=5, help="servo cycles, in [1, 200] (default: %(default)s)")
    p.add_argument("--start-deg", type=float, default=8.0,
                   help="initial tilt error of the target, degrees, within +-12 (default: %(default)s)")
    p.add_argument("--frames-per-cycle", type=int, default=3,
                   help="frames taken during one cycle at 30 fps, in [1, 30] (default: %(default)s)")
    p.add_argument("--gain", type=float, default=1.0,
                   help="servo gain per cycle, in (0, 2) (default: %(default)s: one-step correction)")
    p.add_argument("--deadband-px", type=float, default=0.75,
                   help="hold still while the measured error is at most this, pixels, in [0, 5] (default: %(default)s)")
    p.add_argument("--iterations", type=int, default=20,
                   help="Richardson-Lucy iterations, in [1, 200] (default: %(default)s)")
    p.add_argument("--mount", choices=("tilt", "pan-tilt"), default="tilt",
                   help="the tilt positioner, or a pan carrying a tilt (default: %(default)s)")
    p.add_argument("--seed", type=int, default=7, help="sensor noise seed, >= 0 (default: %(default)s)")
    p.add_argument("--out", default="servo_out_py", help="output folder (default: %(default)s)")
    args = p.parse_args(argv)
    checks = [(1 <= args.cycles <= 200, "--cycles must be in [1, 200]"),
              (abs(args.start_deg) <= 12, "--start-deg must be within +-12 deg"),
              (1 <= args.frames_per_cycle <= 30, "--frames-per-cycle must be in [1, 30]"),
              (0 < args.gain < 2, "--gain must be in (0, 2)"),
              (0 <= args.deadband_px <= 5, "--deadband-px must be in [0, 5]"),
              (1 <= args.iterations <= 200, "--iterations must be in [1, 200]"),
              (args.seed >= 0, "--seed must be >= 0")]
    for ok, message in checks:
        if not ok:
            p.error(message)
    return args


class Camera:
    """The C++ sample's camera: 320x240, fx = fy = 300 px, rows read out in 30 ms at 30 fps."""
    width, height, focal = 320, 240, 300.0
    fps, exposure, line_delay, latency = 30.0, 0.033, 125e-6, 0.004

    def __init__(self, db):
        self.model = db.CameraModel.create(self.focal, self.focal, (self.width - 1) / 2.0, (self.height - 1) / 2.0,
                                           self.width, self.height)
        self.centre = np.array([(self.width - 1) / 2.0, (self.height - 1) / 2.0])

    def view_to_reference(self, points, view):
        """Where the view `view` (a tilt in radians, or a 3x3 rotation) sees `points` of the reference view."""
        view = np.asarray(view, np.float64) if np.ndim(view) == 2 else float(view)
        return self.model.viewToReference(np.asarray(points, np.float64).reshape(-1, 2), view)

    def ray(self, pixel):
        """The direction (camera frame) that `pixel` sees."""
        return np.array([(pixel[0] - self.centre[0]) / self.focal, (pixel[1] - self.centre[1]) / self.focal, 1.0])


def tag_image(cv2, tag_id, cell_px):
    """AprilTag 36h11 `tag_id`: its 8x8-cell black-bordered square plus a white one-cell quiet zone, linear [0, 1]."""
    dictionary = cv2.aruco.getPredefinedDictionary(cv2.aruco.DICT_APRILTAG_36h11)
    square = cv2.aruco.generateImageMarker(dictionary, tag_id, 8 * cell_px, borderBits=1)
    return np.pad(square, cell_px, constant_values=255).astype(np.float32) / 255.0


def textured_plane(height, width, seed=20261122):
    """Grey linear-intensity texture: smooth shading, bars, disks."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:height, 0:width].astype(np.float32)
    img = 0.4 + 0.2 * np.sin(x / 23.0) * np.cos(y / 17.0)
    img += 0.15 * ((x.astype(int) % 13 < 3) & (np.abs(y - 0.7 * height) < height / 14))
    for _ in range(60):
        cy, cx, r = rng.uniform(0, height), rng.uniform(0, width), rng.uniform(3, 18)
        img = np.where((y - cy) ** 2 + (x - cx) ** 2 < r * r, rng.uniform(0.1, 0.8), img)
    return np.clip(img, 0.05, 0.95).astype(np.float32)


class World:
    """The plane as the camera sees it at rest, with margins (max_shift_px down and up, pan_shift_px
    left and right, plus 40 px), and the target placed so that the image centre sees it in the view
    `target` (a tilt in radians, or the mount's orientation, 3x3)."""

    def __init__(self, cv2, camera, target, cell_px=4, max_shift_px=100, pan_shift_px=0):
        self.margin = np.array([pan_shift_px + 40, max_shift_px + 40])
        plane = textured_plane(camera.height + 2 * self.margin[1], camera.width + 2 * self.margin[0])
        self.tags_at_zero, self.offsets = [], []
        for k in range(TAG_IDS):
            offset = (k - (TAG_IDS - 1) / 2.0) * 9 * cell_px  # 9 cells apart: quiet zones shared
            centre = camera.view_to_reference([camera.centre + (0.0, offset)], target)[0]
            tag = tag_image(cv2, k, cell_px)
            top_left = np.rint(centre + self.margin - (tag.shape[0] - 1) / 2.0).astype(int)
            plane[top_left[1]:top_left[1] + tag.shape[0], top_left[0]:top_left[0] + tag.shape[1]] = tag
            self.tags_at_zero.append(top_left - self.margin + (tag.shape[0] - 1) / 2.0)
            self.offsets.append(offset)
        self.sharp = plane

    def target_in_view(self, camera, view):
        """The target's centre (its tags' mean) in the view `view` (a tilt in radians, or an orientation, 3x3)."""
        inverse = np.asarray(view).T if np.ndim(view) == 2 else -view
        return camera.view_to_reference(self.tags_at_zero, inverse).mean(axis=0)


def detect_target(cv2, detector, grey8, offsets):
    """Tags of the target in an 8-bit frame: (all found, tags found, centre or None, corners per tag).
    The centre is the mean of (tag centre - its offset), so a partly seen target still gives one."""
    corners, ids, _ = detector.detectMarkers(grey8)
    found = {}
    for quad, tag_id in zip(corners if ids is not None else [], ids.ravel() if ids is not None else []):
        if 0 <= tag_id < len(offsets) and tag_id not in found:
            a, c, b, d = quad.reshape(4, 2).astype(np.float64)  # corners in order: diagonals a-b and c-d
            r, q = b - a, d - c
            denominator = r[0] * q[1] - r[1] * q[0]
            if abs(denominator) < 1e-9:
                continue
            t = ((c - a)[0] * q[1] - (c - a)[1] * q[0]) / denominator
            found[int(tag_id)] = (a + t * r, quad.reshape(4, 2))
    if not found:
        return False, 0, None, []
    centre = np.mean([p - (0.0, offsets[k]) for k, (p, _) in found.items()], axis=0)
    return len(found) == len(offsets), len(found), centre, [quad for _, quad in found.values()]


def centring_tilt(camera, pixel, theta):
    """The resting tilt whose image centre sees what `pixel` sees at tilt theta (Newton on viewToReference)."""
    target_y = camera.view_to_reference([pixel], theta)[0][1]
    goal, step = theta, 1e-4
    for _ in range(8):
        y0 = camera.view_to_reference([camera.centre], goal)[0][1]
        slope = (camera.view_to_reference([camera.centre], goal + step)[0][1] - y0) / step
        goal -= (y0 - target_y) / slope
    return goal


def configured(db, deblurrer, iterations):
    """The deblurrer with the C++ sample's restoration: row-wise PSFs, `iterations` RL iterations."""
    deblurrer.setPsfModel(db.PSF_ROWS)
    params = deblurrer.getRLParams()
    params.iterations = iterations
    deblurrer.setRLParams(params)
    return deblurrer


class Observer:
    """The camera's side of a cycle: adds the sensor noise to a rendered frame, restores it when it was
    taken while moving, searches both for the target and keeps the frame."""

    def __init__(self, cv2, db, world, seed):
        self.cv2, self.db, self.world, self.seed = cv2, db, world, seed
        self.detector = cv2.aruco.ArucoDetector(cv2.aruco.getPredefinedDictionary(cv2.aruco.DICT_APRILTAG_36h11),
                                                cv2.aruco.DetectorParameters())
        self.frames = []

    def take(self, cycle, shutter, blurred, window, restore):
        """restore(noisy) -> restored frame, or None when nothing moved; frames in window IV stay as taken."""
        db, index = self.db, len(self.frames)
        noisy = db.addSensorNoise(blurred, seed=self.seed * 100003 + index)
        started = time.perf_counter()
        moving = restore is not None and window != db.EXPOSURE_IV
        restored = restore(noisy) if moving else noisy
        restore_ms = 1e3 * (time.perf_counter() - started) if moving else 0.0
        raw8, restored8 = db.linearToSrgb(noisy), db.linearToSrgb(restored)
        frame = dict(cycle=cycle, index=index, window=window, readout_end=shutter.readoutInterval()[1],
                     raw=detect_target(self.cv2, self.detector, raw8, self.world.offsets),
                     restored=detect_target(self.cv2, self.detector, restored8, self.world.offsets),
                     raw8=raw8, restored8=restored8, restore_ms=restore_ms)
        self.frames.append(frame)
        return frame


def latest_sighting(frames, move_start):
    """The target as the latest frame read out after the move began (move_start, None: no move) shows
    it whole; failing that, the one that shows the most tags."""
    seen = (False, 0, None, [])
    for frame in frames:
        # A frame read out wholly before the move began still shows the old view.
        before_move = move_start is not None and frame["readout_end"] <= move_start
        restored = frame["restored"]
        if not before_move and (restored[0] or (not seen[0] and restored[1] >= seen[1])):
            seen = restored
    return seen


def run(args, progress=print):
    if args.mount == "pan-tilt":
        return run_pan_tilt(args, progress)
    import cv2
    import dynblur as db

    camera = Camera(db)
    gain_rad = math.radians(0.05)
    max_level = 400
    plant = db.Plant.create(naturalFreqHz=14.4, dampingRatio=0.12, gain=gain_rad)
    planner = db.SwitchPlanner.create(plant, maxLevel=max_level, mode=db.PLAN_ROBUST)
    deblurrer = configured(db, db.DynamicDeblurrer.create(plant, camera.model), args.iterations)
    max_shift = int(math.ceil(camera.focal * math.tan(math.radians(abs(args.start_deg) * 1.3 + 2))))
    world = World(cv2, camera, math.radians(args.start_deg), max_shift_px=max_shift)
    observer = Observer(cv2, db, world, args.seed)
    # "Moving" for this camera: 0.25 px off the final view, or 0.2 px per exposure (as the C++ sample).
    angle_tol, velocity_tol = 0.25 / camera.focal, 0.2 / camera.focal / camera.exposure
    period = 1.0 / camera.fps

    history_times, history_levels = [], []
    saccade = db.SwitchSchedule(times=[], levels=[], initialLevel=0)
    level, frames, cycles = 0, observer.frames, []

    def take_frame(cycle):
        shutter = db.RollingShutter(frameStart=len(frames) * period, exposure=camera.exposure,
                                    lineDelay=camera.line_delay, rows=camera.height)
        history = db.SwitchSchedule(times=history_times, levels=history_levels, initialLevel=0)
        blurred = db.renderBlurred(world.sharp, plant, history, camera.model, shutter, thetaRef=0.0)
        window = db.classifyExposure(plant, saccade, shutter, angle_tol, velocity_tol)
        restore = (lambda noisy: deblurrer.deblur(noisy, saccade, shutter)) if len(saccade.times) > 0 else None
        return observer.take(cycle, shutter, blurred, window, restore)

    latest = take_frame(-1)["restored"]
    for c in range(args.cycles):
        theta = plant.restingAngle(level)
        true_error = float(np.linalg.norm(world.target_in_view(camera, theta) - camera.centre))
        measured = float(np.linalg.norm(latest[2] - camera.centre)) if latest[1] > 0 else -1.0
        goal = level
        if latest[1] > 0 and measured > args.deadband_px:
            wanted = theta + args.gain * (centring_tilt(camera, latest[2], theta) - theta)
            goal = int(max(-max_level, min(max_level, round(wanted / gain_rad))))
        start = frames[-1]["readout_end"] + camera.latency
        saccade = planner.plan(plant.restingAngle(level), plant.restingAngle(goal), startTime=start)
        history_times += list(saccade.times)
        history_levels += list(saccade.levels)
        level_before, level = level, goal
        latest = latest_sighting([take_frame(c) for _ in range(args.frames_per_cycle)],
                                 saccade.times[0] if len(saccade.times) > 0 else None)
        cycles.append(dict(cycle=c, measured_px=measured, true_px=true_error, from_level=level_before,
                           to_level=level, switches=len(saccade.times)))
        progress(cycle_line(args, cycles[-1], f"level {level_before:4d} -> {level:4d}", frames))
    # The error after the last cycle's saccade.
    theta = plant.restingAngle(level)
    final = dict(true_px=float(np.linalg.norm(world.target_in_view(camera, theta) - camera.centre)),
                 measured_px=float(np.linalg.norm(latest[2] - camera.centre)) if latest[1] > 0 else -1.0)
    return dict(cycles=cycles, frames=frames, final=final)


def cycle_line(args, cycle, move, frames):
    """One progress line: the cycle's error, its move and its frames' windows and detections."""
    windows = " ".join(f"{WINDOW_NAMES.get(f['window'], '?')}[raw {'found' if f['raw'][0] else '-'}, "
                       f"restored {'found' if f['restored'][0] else '-'}]" for f in frames if f["cycle"] == cycle["cycle"])
    return (f"[servo.py] cycle {cycle['cycle'] + 1:2d}/{args.cycles}: error {cycle['measured_px']:6.2f} px "
            f"(true {cycle['true_px']:6.2f}), {move}, frames: {windows}")


def pan_tilt_mount(db, gain_rad, max_level):
    """A pan (0, 1, 0) carrying a tilt (1, 0, 0), each the tilt positioner (14.4 Hz, zeta 0.12)."""
    mount = db.Mount.create()
    for axis in ((0.0, 1.0, 0.0), (1.0, 0.0, 0.0)):
        mount.addAxis(axis, db.Plant.create(naturalFreqHz=14.4, dampingRatio=0.12, gain=gain_rad), -max_level, max_level)
    return mount


def run_pan_tilt(args, progress=print):
    """The loop on a pan-tilt head: the same camera, target, dead band and restoration, two axes."""
    import cv2
    import dynblur as db

    camera = Camera(db)
    gain_rad, max_level, history_start = math.radians(0.05), 400, -1.0
    mount = pan_tilt_mount(db, gain_rad, max_level)
    planner = db.MountPlanner.create(mount, mode=db.PLAN_ROBUST)
    deblurrer = configured(db, db.DynamicDeblurrer.create(camera.model), args.iterations)
    place = math.radians(args.start_deg) / math.sqrt(2.0)  # along the diagonal, as the C++ step scenario
    shift = int(math.ceil(camera.focal * math.tan(math.radians(abs(args.start_deg) * 1.3 + 2))))
    world = World(cv2, camera, mount.orientation([place, place]), max_shift_px=shift, pan_shift_px=shift)
    observer = Observer(cv2, db, world, args.seed)
    angle_tol, velocity_tol = 0.25 / camera.focal, 0.2 / camera.focal / camera.exposure
    period = 1.0 / camera.fps

    def hold(level, at):
        return db.SwitchSchedule(times=[at], levels=[level], initialLevel=level)

    def angles(levels):
        return [mount.getPlant(i).restingAngle(levels[i]) for i in range(2)]

    history = [hold(0, history_start), hold(0, history_start)]  # every switch so far, per axis
    command, levels, frames, cycles = None, [0, 0], observer.frames, []

    def take_frame(cycle):
        shutter = db.RollingShutter(frameStart=len(frames) * period, exposure=camera.exposure,
                                    lineDelay=camera.line_delay, rows=camera.height)
        truth = mount.motion(history)
        blurred = db.renderBlurred(world.sharp, truth, camera.model, shutter, tRef=history_start)
        window = db.classifyExposure(command, shutter, angle_tol, velocity_tol) if command else db.EXPOSURE_IV
        restore = (lambda noisy: deblurrer.deblur(noisy, command, shutter)) if command else None
        return observer.take(cycle, shutter, blurred, window, restore)

    latest = take_frame(-1)["restored"]
    for c in range(args.cycles):
        q = angles(levels)
        true_error = float(np.linalg.norm(world.target_in_view(camera, mount.orientation(q)) - camera.centre))
        measured = float(np.linalg.norm(latest[2] - camera.centre)) if latest[1] > 0 else -1.0
        goal = list(levels)
        if latest[1] > 0 and measured > args.deadband_px:
            # The joint angles whose optical axis points where the measured centre's ray does (exact for a rotation).
            centring = mount.anglesFor(np.asarray(mount.orientation(q)) @ camera.ray(latest[2]), q)
            goal = [int(max(-max_level, min(max_level, round((q[i] + args.gain * (centring[i] - q[i])) / gain_rad))))
                    for i in range(2)]
        command, move_start, switches = None, None, 0
        if goal != levels:
            start = frames[-1]["readout_end"] + camera.latency
            schedules = [s if len(s.times) > 0 else hold(levels[i], start)
                         for i, s in enumerate(planner.plan(q, angles(goal), startTime=start).schedules)]
            for i, s in enumerate(schedules):
                history[i] = db.SwitchSchedule(times=list(history[i].times) + list(s.times),
                                               levels=list(history[i].levels) + list(s.levels), initialLevel=0)
            command = mount.motion(schedules)
            move_start = min(s.times[0] for s in schedules)
            switches = sum(len(s.times) for s in schedules)
        levels_before, levels = levels, goal
        latest = latest_sighting([take_frame(c) for _ in range(args.frames_per_cycle)], move_start)
        cycles.append(dict(cycle=c, measured_px=measured, true_px=true_error,
                           from_level="/".join(map(str, levels_before)), to_level="/".join(map(str, levels)),
                           switches=switches))
        progress(cycle_line(args, cycles[-1], f"pan/tilt levels {cycles[-1]['from_level']} -> {cycles[-1]['to_level']}",
                            frames))
    final = dict(true_px=float(np.linalg.norm(world.target_in_view(camera, mount.orientation(angles(levels)))
                                              - camera.centre)),
                 measured_px=float(np.linalg.norm(latest[2] - camera.centre)) if latest[1] > 0 else -1.0)
    return dict(cycles=cycles, frames=frames, final=final)


def cycles_to_within(report, px):
    """First cycle from which the error (true and measured) stays <= px, counting the state after the
    last saccade as one more cycle; -1 if never."""
    errors = [(c["true_px"], c["measured_px"]) for c in report["cycles"]]
    errors.append((report["final"]["true_px"], report["final"]["measured_px"]))
    first = -1
    for i, (true_px, measured_px) in enumerate(errors):
        if true_px <= px and 0 <= measured_px <= px:
            first = i if first < 0 else first
        else:
            first = -1
    return first


def detection_tally(report):
    """Frames in windows I-III: how many, and in how many the target was found raw and restored."""
    moving = [f for f in report["frames"] if f["window"] in (1, 2, 3)]
    return len(moving), sum(f["raw"][0] for f in moving), sum(f["restored"][0] for f in moving)


def write_outputs(report, out):
    import cv2
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out.mkdir(parents=True, exist_ok=True)
    with open(out / "cycles.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["cycle", "measured_error_px", "true_error_px", "from_level", "to_level", "switches"])
        for c in report["cycles"]:
            w.writerow([c["cycle"], f"{c['measured_px']:.3f}", f"{c['true_px']:.3f}", c["from_level"], c["to_level"],
                        c["switches"]])
    with open(out / "frames.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["cycle", "frame", "window", "raw_found", "raw_tags", "restored_found", "restored_tags", "restore_ms"])
        for fr in report["frames"]:
            w.writerow([fr["cycle"], fr["index"], WINDOW_NAMES.get(fr["window"], "?"), int(fr["raw"][0]), fr["raw"][1],
                        int(fr["restored"][0]), fr["restored"][1], f"{fr['restore_ms']:.1f}"])

    fig, ax = plt.subplots(figsize=(6, 3.2))
    n = len(report["cycles"])
    ax.semilogy(range(n + 1), [max(c["true_px"], 1e-2) for c in report["cycles"]] + [max(report["final"]["true_px"], 1e-2)],
                "o-", label="true")
    measured = [c["measured_px"] for c in report["cycles"]] + [report["final"]["measured_px"]]
    ax.semilogy([i for i, m in enumerate(measured) if m >= 0], [max(m, 1e-2) for m in measured if m >= 0], "s--",
                label="measured (restored frame)")
    ax.axhline(1.0, color="grey", lw=0.8, ls=":")
    ax.set_xlabel("cycle")
    ax.set_ylabel("error of the target centre (px)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(out / "error.png", dpi=120)
    plt.close(fig)

    tiles = []
    for fr in [f for f in report["frames"] if f["window"] in (1, 2, 3)][:6]:
        pair = []
        for key in ("raw", "restored"):
            image = cv2.cvtColor(fr[key + "8"], cv2.COLOR_GRAY2BGR)
            for quad in fr[key][3]:
                cv2.polylines(image, [np.rint(quad).astype(np.int32)], True, (0, 220, 0), 2, cv2.LINE_AA)
            label = f"f{fr['index']} win {WINDOW_NAMES.get(fr['window'], '?')} {key}: " + (
                "target found" if fr[key][0] else f"{fr[key][1]} tag(s)")
            cv2.rectangle(image, (0, 0), (image.shape[1], 16), (0, 0, 0), -1)
            cv2.putText(image, label, (4, 12), cv2.FONT_HERSHEY_SIMPLEX, 0.4,
                        (120, 255, 120) if fr[key][0] else (120, 120, 255), 1, cv2.LINE_AA)
            pair.append(image)
        tiles.append(np.hstack(pair))
    if tiles:
        cv2.imwrite(str(out / "strip.png"), np.vstack(tiles))


def main(argv=None):
    args = parse_args(argv)
    try:
        print(f"[servo.py] step on the {args.mount} mount: target {args.start_deg:.1f} deg off; {args.cycles} cycles, {args.frames_per_cycle} "
              f"frames each; restoring with PSF_ROWS, {args.iterations} RL iterations", flush=True)
        report = run(args, progress=lambda line: print(line, flush=True))
        out = pathlib.Path(args.out)
        write_outputs(report, out)
    except Exception as e:  # a library or I/O error: say what failed and exit non-zero
        print(f"visual_servo.py: {e}", file=sys.stderr)
        return 1
    within = cycles_to_within(report, 1.0)
    frames, raw, restored = detection_tally(report)
    print(f"[servo.py] error <= 1 px from cycle {within} on; windows I-III: {frames} frames, target found raw {raw}, "
          f"restored {restored}; wrote {out}/{{cycles.csv,frames.csv,error.png,strip.png}}")
    return 0 if within >= 0 else 1


if __name__ == "__main__":
    sys.exit(main())
