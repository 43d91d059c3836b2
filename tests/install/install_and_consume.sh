#!/usr/bin/env bash
# Usage: install_and_consume.sh BUILD_DIR CONSUMER_SOURCE WORK_DIR CMAKE
set -euo pipefail
build=$1 consumer=$2 work=$3 cmake=$4
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
