#!/usr/bin/env bash
# Installs what is missing, builds the debug preset (ASan + UBSan) and runs every test.
# In CI (CI set), warnings are errors, the render tests must get an EGL-surfaceless and an
# OSMesa context instead of skipping, glslang must check the shaders, the Vulkan render test
# must get a device (lavapipe), and the demo's window
# test and the OGRE host example (xvfb-run) must be there. Usage: scripts/test.sh [extra ctest arguments]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh
if [ -n "${CI:-}" ]; then
  export SI_WERROR=ON
  export SI_REQUIRE_WINDOW_TEST=ON  # The demo's window under xvfb-run must be tested.
  export SI_REQUIRE_OGRE=ON  # So must the crowd inside OGRE (examples/ogre_host).
  export SI_REQUIRE_GL="${SI_REQUIRE_GL:-egl-surfaceless,osmesa}"
  export SI_REQUIRE_GLSLANG=1  # The offline shader check (tests/gl) must not skip.
  export SI_REQUIRE_VULKAN=1  # The Vulkan back-end's render test (lavapipe) must not skip.
fi
cmake --preset debug
cmake --build --preset debug --parallel "$(nproc)"
ctest --preset debug --parallel "$(nproc)" "$@"
