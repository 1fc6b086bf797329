#!/usr/bin/env bash
# Installs the Debian packages SkinnedInstancing needs that are missing, and prints each one it
# installs. Idempotent; fast (no apt-get at all) when nothing is missing. Run as root (or with
# sudo available). Usage: scripts/deps.sh
set -euo pipefail

packages=(
  # Toolchain
  g++ cmake ninja-build pkg-config python3
  # Libraries (all from Debian; nothing is vendored or downloaded)
  libglm-dev libtinygltf-dev libmeshoptimizer-dev libstb-dev
  libegl-dev libgl-dev libosmesa6-dev libegl-mesa0 libgl1-mesa-dri libglfw3-dev
  python3-glad
  # Tests and benchmarks; glslang compiles every shader offline (tests/gl)
  libgtest-dev libgmock-dev libbenchmark-dev glslang-tools spirv-tools
  # The Vulkan back-end (src/vk): the Vulkan headers and loader (its SPIR-V is compiled by
  # glslang-tools' glslangValidator at build time); its render test's device without a GPU
  # (lavapipe) and the validation layer it runs under
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers
  # The demo's window test: a virtual X server (xvfb-run needs xauth)
  xvfb xauth
  # A real engine as host (examples/ogre_host): OGRE 1.12, its GL3Plus render system
  libogre-1.12-dev
  # The browser page (scripts/web.sh) and its test in headless Chromium (tests/web); emcc's
  # JavaScript optimizer needs node-acorn
  emscripten node-acorn chromium
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
echo "deps: installed ${#missing[@]} packages"
