#!/bin/bash
# Issue 58's CPU goal: A (before) and B (setLivePoses found, stored and committed on the workers)
# side by side, in the order A B B A, two rounds; then the CPU benchmark.
for f in .gl/*.deb; do dpkg -x $f / ; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.gl/lib
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
L=$OUT/live.log
nproc | tee -a $L; nvidia-smi --query-gpu=name,driver_version,clocks.sm --format=csv | tee -a $L
ARGS="--backend egl-device --size 1920x1080 --scenes field --paths instanced,gpu-driven --lods distance --quality-budgets none --error-table-size 0 --sizes 100000 --frames 30 --live 1000,10000"
.gl/live/C/crowd_bench --quick --backend egl-device --size 1920x1080 --scenes field --paths gpu-driven --lods distance --quality-budgets none --error-table-size 0 --sizes 100000 --frames 150 > /dev/null 2>&1
nvidia-smi --query-gpu=clocks.sm --format=csv,noheader | sed 's/^/clock after warm-up: /' | tee -a $L
for r in 1 2; do for b in A C C A; do  # lease 1: A B B A (B: setLivePoses only)
  echo "=== round $r build $b" | tee -a $L
  timeout 120 .gl/live/$b/crowd_bench $ARGS --csv /tmp/x.csv 2>&1 | grep -A8 "^Live poses" | tee -a $L
done; done
nvidia-smi --query-gpu=clocks.sm --format=csv,noheader | sed 's/^/clock at the end: /' | tee -a $L
for r in 1 2 3; do for b in A C; do
  echo "=== cpu round $r build $b" | tee -a $L
  timeout 60 .gl/live/$b/si_crowd_cpu_bench --benchmark_filter='livePoseJoints/joints:60/half:./batch:1' --benchmark_min_time=0.3 2>&1 | grep -E "livePose" | tee -a $L
done; done
