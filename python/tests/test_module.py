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


def test_every_public_name_has_a_docstring():
    missing = [name for name in dir(compiled) if not name.startswith("_")
               and callable(getattr(compiled, name))
               and len((getattr(compiled, name).__doc__ or "").strip().splitlines()) < 1]
    assert missing == []
    assert pn.metrics.__doc__.startswith("metrics(reference")


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
