#!/usr/bin/python3
"""scripts/third-party-plants on hand-made furniture libraries (no third-party file):
every model is extracted with its MTL, a file that is not the measured version is
extracted with a warning, a missing folder or model is an error naming it, and an
extracted y-up OBJ in centimetres stands 1 m tall in `plantnbv plant`.

Usage: test_third_party_plants.py SOURCE_DIR PLANTNBV
"""
import importlib.machinery
import importlib.util
import json
import os
import subprocess
import sys
import tempfile
import zipfile

source_dir, plantnbv = sys.argv[1], sys.argv[2]
script = os.path.join(source_dir, "scripts", "third-party-plants")
loader = importlib.machinery.SourceFileLoader("third_party_plants", script)
spec = importlib.util.spec_from_loader("third_party_plants", loader)
models = importlib.util.module_from_spec(spec)
loader.exec_module(models)

# 1 m along y, 10 cm along z, in centimetres: y up, as the libraries' OBJ files are.
OBJ = "mtllib m.mtl\no Leaf\nusemtl leaf\nv 0 0 0\nv 0 100 0\nv 0 0 10\nf 1 2 3\n"


def run(*args):
    return subprocess.run([sys.executable, script, *args], capture_output=True, text=True)


def check(condition, what):
    if not condition:
        print("FAILED:", what)
        sys.exit(1)


with tempfile.TemporaryDirectory() as tmp:
    furniture = os.path.join(tmp, "furniture")
    os.makedirs(furniture)
    for name, library, folder, obj, *_ in models.MODELS:
        with zipfile.ZipFile(os.path.join(furniture, library), "a") as z:
            z.writestr(f"{folder}/{obj}", OBJ)
            z.writestr(f"{folder}/{os.path.splitext(obj)[0]}.mtl", "newmtl leaf\n")
            z.writestr(f"{folder}/leaf.jpg", "not extracted")
    out = os.path.join(tmp, "models")
    r = run(out, "--from", furniture)
    check(r.returncode == 0, f"extraction: {r.returncode} {r.stderr}")
    lines = r.stdout.splitlines()
    check(len(lines) == len(models.MODELS), f"one line per model: {r.stdout}")
    check(all("warning: SHA-256" in line for line in lines), f"version warnings: {r.stdout}")
    for name, library, folder, obj, *_ in models.MODELS:
        files = sorted(os.listdir(os.path.join(out, name)))
        check(files == sorted([obj, os.path.splitext(obj)[0] + ".mtl"]), f"{name}: {files}")

    name, _, _, obj, *_ = models.MODELS[0]
    plant = os.path.join(tmp, "plant")
    r = subprocess.run([plantnbv, "plant", "--model", os.path.join(out, name, obj),
                        "--model-scale", "0.01", "--model-up-axis", "y", "-o", plant],
                       capture_output=True, text=True)
    check(r.returncode == 0, f"plant: {r.stderr}")
    with open(os.path.join(plant, "anatomy.json")) as f:
        height = json.load(f)["stem"]["top_height_m"]
    check(abs(height - 1.0) < 1e-6, f"height {height}")

    r = run(out, "--from", os.path.join(tmp, "none"))
    check(r.returncode == 1 and "none is missing" in r.stderr, f"no folder: {r.stderr}")
    first = models.MODELS[0]
    with zipfile.ZipFile(os.path.join(furniture, first[1]), "w") as z:
        z.writestr("other/x.obj", OBJ)
    r = run(out, "--from", furniture)
    check(r.returncode == 1 and f"has no {first[2]}/{first[3]}" in r.stderr,
          f"no model: {r.stderr}")
    check(run().returncode == 2, "no argument: usage")
print("third-party-plants: extraction, warnings and errors as documented")
