#!/usr/bin/env bash
# The main job: installs what is missing, builds the release preset and runs the crowd demo on
# the embedded procedural character. Extra arguments go to crowd_demo.
# Usage: scripts/demo.sh [crowd_demo options]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh
cmake --preset release >/dev/null
cmake --build --preset release --target crowd_demo
exec ./build/release/examples/crowd_demo/crowd_demo "$@"
