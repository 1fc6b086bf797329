#!/usr/bin/env bash
# The main job: installs what is missing, builds the release preset and runs the crowd demo on
# the embedded procedural character: a crowd rendered headless into crowd.png (in the current
# folder unless --out says otherwise) and a table of frame statistics. Extra arguments go to
# crowd_demo (--help lists them; --window opens the interactive window instead).
# Usage: scripts/demo.sh [crowd_demo options]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bash "$root/scripts/deps.sh"
(cd "$root" && cmake --preset release >/dev/null && cmake --build --preset release --target crowd_demo)
exec "$root/build/release/examples/crowd_demo/crowd_demo" --headless "$@"
