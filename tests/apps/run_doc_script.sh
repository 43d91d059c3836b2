#!/bin/sh
# Runs the shell script of a doc, as its user would, and checks what it made.
# Usage: run_doc_script.sh DOC MARKER PLANTNBV_BIN_DIR WORK_DIR
#   DOC     a Markdown file; MARKER a line of it (e.g. <!-- ctest: real_robot_loop_script -->)
#           followed by a ```sh block: that block is the script
#   WORK_DIR emptied, then the script runs there (sh -e) with PLANTNBV_BIN_DIR first on PATH
# Checks (docs/real-robot.md's loop): frames/depth.txt lists 5 frames, map.ot is an
# OctoMap .ot file, next.json is JSON with 3 candidates. Exits non-zero otherwise.
set -eu

if [ "$#" -ne 4 ]; then
  echo "usage: $0 DOC MARKER PLANTNBV_BIN_DIR WORK_DIR" >&2
  exit 2
fi
doc=$1 marker=$2 bin_dir=$3 work=$4
fail() {
  echo "run_doc_script: $*" >&2
  exit 1
}
[ -f "$doc" ] || fail "no such doc '$doc'"
[ -x "$bin_dir/plantnbv" ] || fail "no plantnbv in '$bin_dir'"
bin_dir=$(cd "$bin_dir" && pwd) # the script runs in WORK_DIR

rm -rf "$work"
mkdir -p "$work"
script=$work/doc_script.sh
# The ```sh block right after the marker line (blank lines between are allowed).
awk -v marker="$marker" '
  state == 0 && $0 == marker { state = 1; next }
  state == 1 && /^[ \t]*$/ { next }
  state == 1 { if ($0 == "```sh") { state = 2; next } else exit 3 }
  state == 2 && /^```[ \t]*$/ { state = 3; exit }
  state == 2 { print }
  END { if (state != 3) exit 3 }
' "$doc" >"$script" || fail "no \`\`\`sh block right after '$marker' in '$doc'"
[ -s "$script" ] || fail "the block after '$marker' in '$doc' is empty"

echo "run_doc_script: running the block after '$marker' of '$doc' in '$work'"
(cd "$work" && PATH="$bin_dir:$PATH" sh -e "$script") ||
  fail "the script of '$doc' failed (exit $?)"

# What the doc says it makes.
frames=$(grep -v '^[[:space:]]*#' "$work/frames/depth.txt" 2>/dev/null | grep -c '[^[:space:]]' || true)
[ "$frames" = 5 ] || fail "frames/depth.txt lists ${frames:-no} frames, expected 5"
[ -f "$work/map.ot" ] || fail "no map.ot"
[ "$(head -n 1 "$work/map.ot")" = "# Octomap OcTree file" ] ||
  fail "map.ot does not start with OctoMap's .ot header"
/usr/bin/python3 -c '
import json, sys
j = json.load(open(sys.argv[1]))
c = j["candidates"]
assert isinstance(c, list) and len(c) == 3, "%d candidates, expected 3" % len(c)
assert j["best"] == c[0], "best is not candidates[0]"
assert all(len(x["optical_pose"]) == 7 for x in c), "an optical_pose is not 7 numbers"
' "$work/next.json" || fail "next.json is not JSON with 3 candidates"
echo "run_doc_script: ok (5 frames, map.ot, next.json with 3 candidates)"
