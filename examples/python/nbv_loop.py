#!/usr/bin/python3
"""A whole next-best-view loop: a tomato plant, the simulated L515, the occupancy map and
the attention planner on the main stem; F1 of the stem after every view, plotted.
Usage: nbv_loop.py [OUT_DIR]   (writes f1.png, reconstruction.ply and plant.ply there)"""

import pathlib
import sys

import matplotlib
matplotlib.use("Agg")  # files only, no display needed
import matplotlib.pyplot as plt
import plantnbv as pn

out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "nbv_loop")
out.mkdir(parents=True, exist_ok=True)

placed = pn.place_plant(seed=3)                      # plant 3, where the paper has it
roi = placed.rois["main_stem"]
camera = pn.CameraIntrinsics.l515("640x480")
sensor = pn.SimulatedDepthSensor(camera)             # stands in for the robot's camera
sensor.set_plant(placed.plant)
session = pn.Session(seed=1)                         # map, candidates, planner: the paper's
session.camera, session.roi = camera, roi

truth = pn.voxel_grid(pn.sample_mesh(placed.plant.mesh, 500_000), 0.003, centres=True)
truth = pn.crop_to_roi(truth, roi)                   # ground truth of the stem
pose, f1 = [0.646, 0.353, 1.383, 0, 0, -0.383, 0.924], []   # v0 (body frame)
for view in range(1, 7):
    frame = sensor.capture(T_W_C=pose)               # the robot: move, capture
    session.integrate(frame["depth"], camera, frame["T_W_O"])
    occupied = pn.crop_to_roi(session.map.occupied_centres(), roi)
    f1.append(pn.metrics(truth, occupied, rho=0.003).f1)
    nbv = session.next_best_view()                   # ranked candidates
    print(f"view {view}: F1 {f1[-1]:.3f}, next gain {nbv.gain:.0f} bits")
    pose = nbv.best_viewpoint

plt.plot(range(1, len(f1) + 1), f1, marker="o")
plt.xlabel("views"), plt.ylabel("F1 (main stem)"), plt.ylim(0, 1), plt.grid(True)
plt.savefig(out / "f1.png", dpi=100)
pn.write_cloud(out / "reconstruction.ply", session.map.occupied_centres())
pn.write_mesh(out / "plant.ply", placed.plant.mesh)
print(f"wrote {out / 'f1.png'}, reconstruction.ply, plant.ply")
