#!/bin/bash
# Impostor fragment cost: A (the tree: a crowd_bench of ed6124f, whose GL code is cadf50f's) against B (throwaway: cheap_fragment.patch, the
# impostor fragment reading layer 0 alone). Binaries built per docs/performance.md, stripped into .gl/imp/{A,B}.
for f in .gl/*.deb; do dpkg -x $f / ; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.gl/lib
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
L=$OUT/imp.log
nvidia-smi --query-gpu=name,driver_version,clocks.sm --format=csv | tee -a $L
ARGS="--quick --backend egl-device --size 1920x1080 --scenes field --lods screen --quality-budgets none --error-table-size 0 --part-lod --impostor --frames 30 --gpu-passes --paths gpu-driven --sizes 100000,1000000"
.gl/imp/A/crowd_bench $ARGS > /dev/null 2>&1
nvidia-smi --query-gpu=clocks.sm --format=csv,noheader | sed 's/^/clock after warm-up: /' | tee -a $L
for r in 1 2; do for b in A B B A; do
  echo "=== round $r build $b" | tee -a $L
  timeout 100 .gl/imp/$b/crowd_bench $ARGS --csv /tmp/x.csv 2>&1 | grep -E "^field +gpu-driven" | tee -a $L
done; done
nvidia-smi --query-gpu=clocks.sm --format=csv,noheader | sed 's/^/clock at the end: /' | tee -a $L
