#!/usr/bin/env bash
# Usage: install_and_consume.sh BUILD_DIR CONSUMER_SOURCE WORK_DIR CMAKE [ROBOT_CONSUMER_SOURCE
#        [PYTHON]]
# Installs the build into WORK_DIR/prefix, then builds and runs two projects of others
# against it: CONSUMER_SOURCE (plantnbv::metrics only) and ROBOT_CONSUMER_SOURCE (default:
# robot_consumer beside CONSUMER_SOURCE; plantnbv::session and plantnbv::io only, a
# 3-frame loop), and checks that what a robot links holds no simulator. With PYTHON (the
# interpreter the module was built for), imports the installed Python package in a clean
# process and computes metrics with it.
set -euo pipefail
build=$1 consumer=$2 work=$3 cmake=$4
robot_consumer=${5:-$(dirname "$consumer")/robot_consumer}
python=${6:-}
rm -rf "$work"
"$cmake" --install "$build" --prefix "$work/prefix" >"$work.install.log" 2>&1 ||
  { cat "$work.install.log"; exit 1; }
test -f "$work/prefix/include/plantnbv/metrics/reconstruction_metrics.h"
test -f "$work/prefix/lib/cmake/plantnbv/plantnbvConfig.cmake"

# metrics stands alone: no VTK or Embree in what it links.
if ldd "$work"/prefix/lib/libplantnbv_metrics.so | grep -Ei 'vtk|embree'; then
  echo "libplantnbv_metrics links VTK or Embree" >&2; exit 1
fi

"$cmake" -S "$consumer" -B "$work/consumer-build" -G Ninja \
  -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release
"$cmake" --build "$work/consumer-build"
out=$("$work/consumer-build/consumer")
echo "$out"
[ "$out" = "f1=1 chamfer=0.002" ]

# The robot's consumer: session + io, frames written, read back, integrated, planned.
"$cmake" -S "$robot_consumer" -B "$work/robot-consumer-build" -G Ninja \
  -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release
"$cmake" --build "$work/robot-consumer-build"
robot="$work/robot-consumer-build/robot_consumer"
out=$("$robot")
echo "$out"
[ "$out" = "frames=3 candidates=27 best_gain>0=1 occupied>0=1" ]

# What a robot links holds no simulator: no Embree, no plant generator, no ray caster,
# no VTK and no libpcl_io (which loads VTK), in anything loaded with the robot's program
# and the three libraries it needs (ldd: every library loaded, not only the direct ones).
lib="$work/prefix/lib"
status=0
for f in "$robot" "$lib/libplantnbv_session.so" "$lib/libplantnbv_io.so" \
         "$lib/libplantnbv_camera.so"; do
  deps=$(ldd "$f")
  if grep -Ei 'not found' <<<"$deps"; then
    echo "$f: a library it needs is not found" >&2; status=1
  fi
  if grep -Ei 'embree|libplantnbv_(plant|sensor|viz|experiment|scenario)\.' <<<"$deps"; then
    echo "$f links Embree or a simulator module of plantnbv" >&2; status=1
  fi
  if grep -Ei 'vtk|pcl_io' <<<"$deps"; then
    echo "$f loads VTK or libpcl_io" >&2; status=1
  fi
done

if [ -n "$python" ]; then
  site="$work/prefix/lib/python3/dist-packages"
  test -f "$site/plantnbv/_plantnbv.pyi"
  # A fresh process with nothing of the build tree: only the installed package's path.
  out=$(cd / && env -i PATH=/usr/bin:/bin PYTHONPATH="$site" "$python" -c '
import numpy as np, plantnbv
assert plantnbv.__file__.startswith("'"$site"'"), plantnbv.__file__
m = plantnbv.metrics(np.zeros((2, 3)), np.full((2, 3), 0.001), rho=0.003)
print("python f1=%g version=%s" % (m.f1, plantnbv.__version__))')
  echo "$out"
  [[ "$out" =~ ^python\ f1=1\ version=[0-9]+\.[0-9]+\.[0-9]+$ ]] ||
    { echo "the installed Python package does not work" >&2; status=1; }
fi
exit $status
