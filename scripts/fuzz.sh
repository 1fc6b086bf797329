#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan + libFuzzer) and runs each for a while.
# Usage: scripts/fuzz.sh [seconds per target, default 60]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
bash scripts/deps.sh
for p in clang libclang-rt-14-dev; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    echo "fuzz: installing $p"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "$p"
  fi
done
build=build/fuzz
CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DSI_SANITIZE=ON -DSI_BUILD_FUZZERS=ON -DSI_BUILD_TESTS=OFF -DSI_BUILD_EXAMPLES=OFF \
  -DSI_BUILD_BENCHMARKS=OFF -DSI_WITH_GL=OFF -DSI_INSTALL=OFF -DSI_WITH_GLTF=ON >/dev/null
cmake --build "$build" --target si_palette_fuzz si_gltf_fuzz si_write_fuzz_seeds
corpus="$build/corpus/palette"
mkdir -p "$corpus"
"$build/tests/fuzz/si_write_fuzz_seeds" "$corpus"
echo "fuzz: si_palette_fuzz for ${seconds}s"
"$build/tests/fuzz/si_palette_fuzz" "$corpus" -max_total_time="$seconds" -max_len=65536 \
  -print_final_stats=1
# glTF: seeded with the sample assets' self-contained files (.glb and embedded .gltf).
gltf_corpus="$build/corpus/gltf"
mkdir -p "$gltf_corpus"
assets="$(pwd)/../shared/assets"
for f in "$assets"/*/glTF-Binary/*.glb "$assets"/*/glTF-Embedded/*.gltf; do
  [ -f "$f" ] && cp "$f" "$gltf_corpus/"
done
echo "fuzz: si_gltf_fuzz for ${seconds}s"
"$build/tests/fuzz/si_gltf_fuzz" "$gltf_corpus" -max_total_time="$seconds" -max_len=1048576 \
  -rss_limit_mb=4096 -print_final_stats=1
