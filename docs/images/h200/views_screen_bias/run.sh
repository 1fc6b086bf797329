#!/bin/bash
# Device run: main view + 3 cascades at screen LODs with impostors, cascades' LOD bias 1, 2, 3.
for f in .gl/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.gl/lib __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
B=.gl/live/crowd_bench
common="--quick --backend egl-device --size 1920x1080 --scenes field --lods screen --quality-budgets none --error-table-size 0 --paths gpu-driven --part-lod --impostor --gpu-passes"
timeout 60 $B $common --sizes 1000000 --frames 60 --csv /tmp/w.csv > $OUT/warm.log 2>&1
timeout 60 $B $common --sizes 1000000 --frames 60 --csv /tmp/w.csv > $OUT/warm2.log 2>&1
nvidia-smi --query-gpu=clocks.sm --format=csv | tee $OUT/gpu.txt
for bias in 1 2 3 4; do
  timeout 120 $B $common --sizes 100000,1000000 --frames 20 --views 1,4 --views-lod-bias $bias --csv /tmp/b$bias.csv > $OUT/bias$bias.log 2>&1
  nvidia-smi --query-gpu=clocks.sm --format=csv,noheader | tee -a $OUT/gpu.txt
done
