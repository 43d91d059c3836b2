"""plantnbv: attention-driven next-best-view planning for plant reconstruction.

NumPy arrays in and out: clouds are (N, 3) float32 or float64 arrays, labels (N,)
integers, poses (7,) [x, y, z, qx, qy, qz, qw] or 4x4 matrices, depth images (H, W)
metres. Frames: a camera's body frame (x forward, y left, z up) is T_W_C, its optical
frame (z forward, x right, y down; OpenCV, ROS, TUM) T_W_O. docs/python.md has the tour.
"""

from ._plantnbv import *  # noqa: F401,F403  (the compiled module)
from ._plantnbv import __doc__ as _compiled_doc  # noqa: F401

__version__ = "@PROJECT_VERSION@"
