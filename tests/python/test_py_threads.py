# SPDX-License-Identifier: Apache-2.0
"""The GIL is released during long calls: another Python thread runs meanwhile, and two threads
restoring frames at once get the same results as one after the other."""
import threading
import time

import numpy as np

from conftest import make_scene


def test_python_thread_runs_while_deblur_works(db, small_setup):
    plant, sched, cam, shutter = small_setup
    sharp = make_scene(120, 160)
    blurred = db.renderBlurred(sharp, plant, sched, cam, shutter)
    deb = db.DynamicDeblurrer.create(plant, cam)
    deb.setRLParams(db.RLParams(iterations=60))
    ticks, stop = [], threading.Event()

    def ticker():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    th = threading.Thread(target=ticker)
    th.start()
    time.sleep(0.02)
    t0 = time.perf_counter()
    deb.deblur(blurred, sched, shutter)
    t1 = time.perf_counter()
    stop.set()
    th.join()
    inside = [x for x in ticks if t0 < x < t1]
    print(f"[ measured ] deblur {1e3 * (t1 - t0):.0f} ms, a Python thread ticked {len(inside)} times meanwhile")
    assert t1 - t0 > 0.02
    assert len(inside) >= max(3, int(0.2 * (t1 - t0) / 0.0015))


def test_two_threads_restore_concurrently(db, small_setup):
    plant, sched, cam, shutter = small_setup
    frames = [db.renderBlurred(make_scene(120, 160, seed=s), plant, sched, cam, shutter) for s in (1, 2)]
    serial = [db.DynamicDeblurrer.create(plant, cam).deblur(f, sched, shutter) for f in frames]
    results, spans = [None, None], [None, None]

    def work(i):
        deb = db.DynamicDeblurrer.create(plant, cam)
        start = time.perf_counter()
        results[i] = deb.deblur(frames[i], sched, shutter)
        spans[i] = (start, time.perf_counter())

    threads = [threading.Thread(target=work, args=(i,)) for i in range(2)]
    for th in threads:
        th.start()
    for th in threads:
        th.join(timeout=120)
        assert not th.is_alive(), "deadlock"
    overlap = min(spans[0][1], spans[1][1]) - max(spans[0][0], spans[1][0])
    print(f"[ measured ] two concurrent deblur calls overlapped for {1e3 * overlap:.0f} ms "
          f"(durations {1e3 * (spans[0][1] - spans[0][0]):.0f} / {1e3 * (spans[1][1] - spans[1][0]):.0f} ms)")
    assert overlap > 0
    for got, ref in zip(results, serial):
        np.testing.assert_allclose(got, ref, atol=1e-5)


def test_ode_plant_callback_from_released_call(db):
    """A Python rhs called from a GIL-released plan/response does not deadlock."""
    wn, z, g = 2 * np.pi * 14.4, 0.12, np.deg2rad(1)
    plant = db.OdePlant.create(lambda t, x, u: [x[1], wn * wn * (g * u - x[0]) - 2 * z * wn * x[1]], 2,
                               lambda level: [g * level, 0.0], 14.4, 0.12, g)
    sched = db.SwitchSchedule([0.0], [5])
    out = [None]
    th = threading.Thread(target=lambda: out.__setitem__(0, plant.response(sched, np.linspace(0, 0.1, 50))))
    th.start()
    th.join(timeout=60)
    assert not th.is_alive()
    assert abs(out[0][-1] - db.Plant.create(14.4, 0.12, g).response(sched, [0.1])[0]) < 1e-6
