#!/usr/bin/env bash
# Side by side on one machine in one run: a baseline si_crowd_cpu_bench (another build: the
# baseline commit's library, best with this tree's tests/bench sources so both know
# the same configurations) and this tree's release build, alternately for ROUNDS rounds (default
# 3), medians of 3 repetitions each, the same FILTER on both. Usage:
#   scripts/crowd_cpu_compare.sh BASELINE_BENCH [ROUNDS] [FILTER]
# FILTER selects the configurations (default: 1 and 2 threads).
set -euo pipefail
cd "$(dirname "$0")/.."
base=${1:?usage: scripts/crowd_cpu_compare.sh BASELINE_BENCH [ROUNDS] [FILTER]}
rounds=${2:-3}
filter=${3:-threads:(1|2)/}
now=build/release/tests/bench/si_crowd_cpu_bench
[[ -x "$now" ]] || { echo "build the release preset first: $now is missing" >&2; exit 1; }
for ((r = 1; r <= rounds; ++r)); do
  for run in baseline now; do
    echo "# round $r: $run"
    bin=$base
    [[ $run == now ]] && bin=$now
    "$bin" --benchmark_filter="$filter" --benchmark_repetitions=3 \
      --benchmark_report_aggregates_only=true | grep median
  done
done
