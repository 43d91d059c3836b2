#!/usr/bin/python3
"""What the Python layer costs (docs/performance.md, "Python"): the same work called
from NumPy and by the C++ tool, medians of REPEATS runs each.

  metrics: 300k vs 300k points. C++: `plantnbv eval --json`'s metrics_ms (both search
           trees and compute(), file loading excluded). Python: plantnbv.metrics(a, b)
           from float64 NumPy arrays, conversion included.
  plan:    one planning step on a map of two views of plant 3 (27 candidates, main
           stem). C++: `plantnbv plan --json`'s timings_ms.plan (the planner's
           compute(), in a fresh process), and the same compute() timed inside the
           Python call (NextBestView.timings_ms["total"], a warm process). Python:
           Session.next_best_view() wall time on a fresh session that read the same map
           (snapshot rebuilt, as in the tool), ranking and arrays included.
  arrays:  reading an (N, 3) array into the library: crop_to_roi of 1M random points
           with an empty ROI (little but that one pass), float32 and float64, C and
           Fortran order.

Usage: PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead.py build/bin/plantnbv
       [REPEATS] [THREADS]
"""

import json
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import plantnbv as pn

V0 = [0.646, 0.353, 1.383, 0, 0, -0.383, 0.924]


def tool(cli, *args):
    done = subprocess.run([cli, *map(str, args)], capture_output=True, text=True, check=True)
    return json.loads(done.stdout)


def median_ms(call, repeats):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        times.append((time.perf_counter() - start) * 1000.0)
    return statistics.median(times)


def main():
    cli = sys.argv[1]
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 15
    threads = int(sys.argv[3]) if len(sys.argv) > 3 else 0
    work = pathlib.Path(tempfile.mkdtemp(prefix="plantnbv-python-bench-"))

    # metrics: two clouds of 300k points near a plant's surface.
    placed = pn.place_plant(seed=3)
    reference = pn.sample_mesh(placed.plant.mesh, 300_000, seed=1).astype(np.float64)
    rng = np.random.default_rng(2)
    reconstruction = pn.sample_mesh(placed.plant.mesh, 300_000, seed=2).astype(np.float64)
    reconstruction += rng.normal(0, 0.001, reconstruction.shape)
    pn.write_cloud(work / "t.pcd", reference)
    pn.write_cloud(work / "r.pcd", reconstruction)
    # The tool reads float32: give Python the same values.
    reference = pn.read_cloud(work / "t.pcd").astype(np.float64)
    reconstruction = pn.read_cloud(work / "r.pcd").astype(np.float64)
    cpp = statistics.median(
        tool(cli, "eval", "--reference", work / "t.pcd", "--reconstruction", work / "r.pcd",
             "--json")["metrics_ms"] for _ in range(repeats))
    py = median_ms(lambda: pn.metrics(reference, reconstruction, rho=0.003, threads=threads),
                   repeats)
    m = pn.metrics(reference, reconstruction)
    print(f"metrics 300k vs 300k: C++ {cpp:.1f} ms, Python {py:.1f} ms "
          f"({py / cpp:.3f}x), f1 {m.f1:.4f}")

    # plan: the map of two views, planned on by the tool and by a Python session.
    camera = pn.CameraIntrinsics.l515("640x480")
    sensor = pn.SimulatedDepthSensor(camera)
    sensor.set_plant(placed.plant)
    session = pn.Session()
    for pose in (V0, [0.62, -0.35, 1.2, 0.0, 0.0, 0.3827, 0.9239]):
        frame = sensor.capture(T_W_C=pose)
        session.integrate(frame["depth"], camera, frame["T_W_O"])
    session.write_map(work / "map.ot")
    pn.write_roi(work / "stem.yaml", placed.rois["main_stem"])
    args = ["--map", work / "map.ot", "--roi", work / "stem.yaml", "--json"]
    if threads:
        args += ["--threads", threads]
    cpp = statistics.median(tool(cli, "plan", *args)["timings_ms"]["plan"]
                            for _ in range(repeats))

    def python_step():
        s = pn.Session(threads=threads)
        s.camera = camera
        s.roi = placed.rois["main_stem"]
        s.read_map(work / "map.ot")
        start = time.perf_counter()
        nbv = s.next_best_view()
        return (time.perf_counter() - start) * 1000.0, nbv.timings_ms["total"]

    steps = [python_step() for _ in range(repeats)]
    py = statistics.median(wall for wall, _ in steps)
    inner = statistics.median(c for _, c in steps)
    print(f"one planning step: C++ tool {cpp:.2f} ms, C++ inside the Python call "
          f"{inner:.2f} ms, Python {py:.2f} ms ({py / cpp:.3f}x the tool, "
          f"{py / inner:.3f}x the same process)")

    points = np.random.default_rng(0).random((1_000_000, 3))
    for name, array in [("float32 C", points.astype(np.float32)), ("float64 C", points),
                        ("float64 Fortran", np.asfortranarray(points))]:
        ms = median_ms(lambda: pn.crop_to_roi(array, pn.Roi()), repeats)
        print(f"reading 1M points from {name}: {ms:.1f} ms")


if __name__ == "__main__":
    main()
