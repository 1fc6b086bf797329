#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan + libFuzzer) and runs them all at once,
# spread over the machine's cores, then prints one row per target: executions, coverage (edges
# libFuzzer counted), corpus size and crashes (the inputs it saved under build/fuzz/crashes/).
# Seeds: generated palettes, call sequences and hostile glTFs, assets/, tests/regressions/inputs/.
#
# Usage: scripts/fuzz.sh [-t SECONDS] [-w WORKERS] [-u SECONDS] [--build-only] [--run-only]
#                        [TARGET...]
#   -t SECONDS   fuzzing time of each target (default 60)
#   -u SECONDS   wall time one input may take before it is saved as a timeout (default 60;
#                raise it when the fuzzers share the machine at a low priority: the largest
#                seeds take some 10 s of CPU each in this build)
#   -w WORKERS   processes per target (libFuzzer -jobs/-workers; default: cores / targets, >= 1)
#   --build-only build the targets and seeds, do not fuzz (for carrying them to another machine)
#   --run-only   fuzz with what build/fuzz holds (built here or carried)
#   TARGET       palette palette_crowd crowd_api gltf gltf_bake (default: all)
# Exit status: 0 when no target crashed, 1 otherwise.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=60 workers=0 unit=60 build=1 run=1 targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    -t) seconds="$2"; shift 2 ;;
    -w) workers="$2"; shift 2 ;;
    -u) unit="$2"; shift 2 ;;
    --build-only) run=0; shift ;;
    --run-only) build=0; shift ;;
    -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
    *) targets+=("$1"); shift ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=(palette palette_crowd crowd_api gltf gltf_bake)
out=build/fuzz
assets="$(pwd)/assets"
regressions="$(pwd)/tests/regressions/inputs"

if [ "$build" = 1 ]; then
  bash scripts/deps.sh
  for p in clang libclang-rt-14-dev; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      echo "fuzz: installing $p"
      DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "$p"
    fi
  done
  CC=clang CXX=clang++ cmake -S . -B "$out" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DSI_SANITIZE=ON -DSI_BUILD_FUZZERS=ON -DSI_BUILD_TESTS=OFF -DSI_BUILD_EXAMPLES=OFF \
    -DSI_BUILD_BENCHMARKS=OFF -DSI_BUILD_TOOLS=OFF -DSI_WITH_GL=OFF -DSI_INSTALL=OFF \
    -DSI_WITH_GLTF=ON >/dev/null
  cmake --build "$out" --target si_write_fuzz_seeds $(printf 'si_%s_fuzz ' "${targets[@]}")
  # Seeds, one folder per target (each target's corpus grows in its own folder).
  mkdir -p "$out/seeds/palette" "$out/seeds/crowd-api" "$out/seeds/gltf"
  "$out/tests/fuzz/si_write_fuzz_seeds" palette "$out/seeds/palette"
  "$out/tests/fuzz/si_write_fuzz_seeds" crowd-api "$out/seeds/crowd-api"
  "$out/tests/fuzz/si_write_fuzz_seeds" gltf "$out/seeds/gltf"  # Hostile files of our own.
  for f in "$assets"/*/glTF-Binary/*.glb "$assets"/*/glTF-Embedded/*.gltf; do
    [ -f "$f" ] && cp "$f" "$out/seeds/gltf/"
  done
  for f in "$regressions"/*.sipal; do [ -f "$f" ] && cp "$f" "$out/seeds/palette/"; done
  for f in "$regressions"/*.gl*; do [ -f "$f" ] && cp "$f" "$out/seeds/gltf/"; done
fi
[ "$run" = 1 ] || exit 0

cores=$(nproc)
[ "$workers" -gt 0 ] || workers=$(( cores / ${#targets[@]} > 0 ? cores / ${#targets[@]} : 1 ))
seed_of() {
  case "$1" in
    palette|palette_crowd) echo palette ;;
    crowd_api) echo crowd-api ;;
    gltf|gltf_bake) echo gltf ;;
  esac
}
echo "fuzz: ${#targets[@]} targets x $workers workers for ${seconds}s on $cores cores"
for t in "${targets[@]}"; do
  dir="$out/run/$t"
  rm -rf "$dir"
  mkdir -p "$dir/corpus" "$out/crashes/$t"
  cp "$out/seeds/$(seed_of "$t")"/* "$dir/corpus/" 2>/dev/null || true
  # Each of the `workers` jobs fuzzes for `seconds`, sharing the corpus; logs in $dir.
  (cd "$dir" && exec "../../tests/fuzz/si_${t}_fuzz" corpus -jobs="$workers" -workers="$workers" \
     -max_total_time="$seconds" -max_len=1048576 -rss_limit_mb=3072 -timeout="$unit" \
     -print_final_stats=1 -artifact_prefix="../../crashes/$t/" >/dev/null 2>&1) &
done
wait || true

# One row per target from the workers' final statistics.
status=0
printf '%-14s %14s %10s %10s %8s\n' target executions coverage corpus crashes
for t in "${targets[@]}"; do
  dir="$out/run/$t"
  execs=$(cat "$dir"/fuzz-*.log 2>/dev/null | awk '/stat::number_of_executed_units/ {s += $2} END {print s + 0}')
  cov=$(cat "$dir"/fuzz-*.log 2>/dev/null | grep -o 'cov: [0-9]*' | awk '{if ($2 > m) m = $2} END {print m + 0}')
  corpus=$(ls "$dir/corpus" | wc -l)
  crashes=$(ls "$out/crashes/$t" | grep -c -E '^(crash|leak|timeout|oom)-' || true)
  printf '%-14s %14s %10s %10s %8s\n' "$t" "$execs" "$cov" "$corpus" "$crashes"
  [ "$crashes" -eq 0 ] || status=1
done
exit $status
