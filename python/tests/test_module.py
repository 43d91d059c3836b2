"""The package as a user meets it: stubs for editors, docstrings, long calls that let
other Python threads run."""

import ast
import pathlib
import threading
import time

import plantnbv as pn
import plantnbv._plantnbv as compiled


def test_the_stubs_parse_and_name_everything_public():
    stub = pathlib.Path(compiled.__file__).with_name("_plantnbv.pyi")
    tree = ast.parse(stub.read_text())
    defined = {node.name for node in tree.body if isinstance(node, (ast.ClassDef, ast.FunctionDef))}
    defined |= {node.target.id for node in tree.body if isinstance(node, ast.AnnAssign)}
    public = {name for name in dir(compiled) if not name.startswith("_")}
    assert public - defined == set()
    session = next(n for n in tree.body if isinstance(n, ast.ClassDef) and n.name == "Session")
    methods = {n.name for n in session.body if isinstance(n, ast.FunctionDef)}
    assert {"integrate", "next_best_view", "set_candidates", "write_map"} <= methods


def described(obj):
    """The docstring without pybind11's signature lines (which every function has)."""
    lines = (obj.__doc__ or "").strip().splitlines()
    return [l for l in lines if l.strip() and not l.startswith(obj.__name__ + "(")
            and l.strip() != "Overloaded function." and not l[:3].rstrip(". ").isdigit()]


def test_every_public_name_has_a_docstring_beyond_its_signature():
    missing = [name for name in dir(compiled) if not name.startswith("_")
               and callable(getattr(compiled, name)) and not described(getattr(compiled, name))]
    assert missing == []
    assert pn.metrics.__doc__.startswith("metrics(reference")
    assert described(pn.Session.next_best_view) and described(pn.Session)


def test_long_calls_release_the_gil(placed):
    done = threading.Event()
    ticks = []

    def trial():
        pn.run_trial(placed, views=2, threads=1)
        done.set()

    worker = threading.Thread(target=trial)
    start = time.perf_counter()
    worker.start()
    while not done.is_set():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    # A call that held the GIL would leave this loop no chance to run meanwhile.
    assert len(ticks) > 20, (len(ticks), time.perf_counter() - start)


def test_one_session_used_from_two_threads_waits_instead_of_racing(sensor, camera):
    frames = [sensor.capture(T_W_C=pose) for pose in
              ([0.646, 0.353, 1.383, 0, 0, -0.383, 0.924], [0.62, -0.35, 1.2, 0, 0, 0.3827, 0.9239])]
    session = pn.Session()
    session.camera = camera
    errors = []

    def integrate():
        try:
            for _ in range(3):
                for f in frames:
                    session.integrate(f["depth"], camera, f["T_W_O"])
        except Exception as e:  # noqa: BLE001 (reported below)
            errors.append(e)

    worker = threading.Thread(target=integrate)
    worker.start()
    gains = []
    while worker.is_alive():
        gains.append(session.next_best_view().gain)
        session.map.counts()
    worker.join()
    assert errors == [] and gains
    alone = pn.Session()
    for _ in range(3):
        for f in frames:
            alone.integrate(f["depth"], camera, f["T_W_O"])
    assert alone.map.counts() == session.map.counts()


def test_keyword_arguments_of_the_wrong_type_are_named():
    import pytest
    with pytest.raises(TypeError, match="OccupancyMap: resolution_m: expected float, got str"):
        pn.OccupancyMap(resolution_m="fine")
