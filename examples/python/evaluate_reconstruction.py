#!/usr/bin/python3
"""Scores your own reconstruction (a PLY or PCD cloud) against a plant mesh, as
`plantnbv eval` does: the mesh is sampled and reduced to voxel centres at the resolution,
then Chamfer distance and precision / recall / F1 at rho (default: the resolution).
Usage: evaluate_reconstruction.py RECONSTRUCTION MESH [RESOLUTION_M] [ROI.yaml]"""

import sys

import plantnbv as pn

if len(sys.argv) < 3:
    sys.exit(__doc__)
reconstruction_path, mesh_path = sys.argv[1], sys.argv[2]
resolution = float(sys.argv[3]) if len(sys.argv) > 3 else 0.003

try:
    reconstruction = pn.read_cloud(reconstruction_path)          # (N, 3) float32
    reference = pn.read_geometry(mesh_path, resolution_m=resolution)
    if len(sys.argv) > 4:                                        # score one region only
        roi = pn.read_roi(sys.argv[4])
        reference, reconstruction = pn.crop_to_roi(reference, roi), pn.crop_to_roi(reconstruction, roi)
except (OSError, ValueError) as e:                               # plantnbv's errors are these
    sys.exit(f"evaluate_reconstruction: {e}")

m = pn.metrics(reference, reconstruction, rho=resolution)
print(f"{m.reconstruction_points} reconstruction and {m.reference_points} reference points")
print(f"precision {m.precision:.4f}  recall {m.recall:.4f}  F1 {m.f1:.4f}")
print(f"Chamfer {m.chamfer * 1000:.2f} mm (accuracy {m.mean_dist_reconstruction_to_reference * 1000:.2f} mm, "
      f"completeness {m.mean_dist_reference_to_reconstruction * 1000:.2f} mm)")
