"""Fixtures of the Python tests. ctest runs them with the interpreter the module was built
for, PYTHONPATH at the built package and PLANTNBV_CLI at the command-line tool."""

import json
import os
import subprocess

import numpy as np
import pytest

import plantnbv as pn

V0 = np.array([0.646, 0.353, 1.383, 0.0, 0.0, -0.383, 0.924])  # the paper's v0 (body)


@pytest.fixture(scope="session")
def cli():
    """Runs the plantnbv tool; returns its stdout (JSON parsed with json=True)."""
    path = os.environ.get("PLANTNBV_CLI")
    if not path:
        pytest.skip("PLANTNBV_CLI is not set (the tool is not built)")

    def run(*args, parse_json=False):
        done = subprocess.run([path, *map(str, args)], capture_output=True, text=True)
        assert done.returncode == 0, done.stderr
        return json.loads(done.stdout) if parse_json else done.stdout

    return run


@pytest.fixture(scope="session")
def placed():
    """Plant 3 of the default set, placed as trials place it."""
    return pn.place_plant(seed=3)


@pytest.fixture(scope="session")
def camera():
    return pn.CameraIntrinsics.l515("320x240")


@pytest.fixture(scope="session")
def sensor(placed, camera):
    s = pn.SimulatedDepthSensor(camera)
    s.set_plant(placed.plant)
    return s
