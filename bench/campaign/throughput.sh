#!/usr/bin/env bash
# Campaign throughput (docs/performance.md, "Campaigns"): the quick campaign
# (data/campaigns/quick.yaml, 156 trials of 10 views) from an empty directory with 1 and
# 2 workers, and the Slurm test's 6-trial array on the single-node test cluster with 1
# and 2 array tasks (tests/slurm/slurm_campaign_test.sh; needs root and Slurm).
# Run it on a quiet machine.
# Usage: bench/campaign/throughput.sh [BUILD_DIR] [REPEATS]   (default: build 1)
set -euo pipefail
cd "$(dirname "$0")/../.."
build=$(readlink -f "${1:-build}")
repeats=${2:-1}
tool="$build/bin/plantnbv"
[ -x "$tool" ] || { echo "throughput: $tool not found: build first" >&2; exit 1; }
work=$(mktemp -d /tmp/plantnbv-throughput.XXXXXX)
trap 'rm -rf "$work"' EXIT
now() { date +%s.%N; }

echo "quick campaign (156 trials), $(nproc) cores"
for jobs in 1 2; do
  for ((r = 1; r <= repeats; r++)); do
    rm -rf "$work/quick"
    t=$(now)
    "$tool" campaign run data/campaigns/quick.yaml -o "$work/quick" -j "$jobs" >/dev/null
    awk -v a="$t" -v b="$(now)" -v j="$jobs" 'BEGIN {
      s = b - a; printf "  -j %d: %.0f s, %.1f trials/min\n", j, s, 156 * 60 / s }'
  done
done

if command -v slurmctld >/dev/null 2>&1 && [ "$(id -u)" -eq 0 ]; then
  echo "Slurm test cluster, 6 trials (submit to the last task done)"
  for k in 6 3; do
    for ((r = 1; r <= repeats; r++)); do
      PLANTNBV_SLURM_TEST_TRIALS_PER_TASK=$k tests/slurm/slurm_campaign_test.sh "$tool" \
        "$build/tests/compare_campaign_results" | grep -E "COMPLETED|local run" |
        sed "s/^/  $((6 / k)) task(s): /"
    done
  done
else
  echo "Slurm: skipped (needs root and the packages slurmd slurmctld slurm-client munge)"
fi
