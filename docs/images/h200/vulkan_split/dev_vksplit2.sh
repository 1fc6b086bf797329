#!/bin/bash
# Device run: the 100k field on the GPU-driven path, si::vk against si::gl, with and without
# impostors (crowd_bench --vulkan --gpu-passes), two rounds interleaved.
for f in .gl/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.gl/lib:$PWD/.gl/vvl/usr/lib/x86_64-linux-gnu
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
common="--quick --backend egl-device --size 1920x1080 --quality-budgets none"
timeout 60 .gl/live/crowd_bench $common --lods distance --error-table-size 0 --scenes field --paths instanced --sizes 100000 --frames 40 --csv /tmp/w.csv > /tmp/warm.log 2>&1
nvidia-smi --query-gpu=clocks.sm --format=csv,noheader | tee $OUT/gpu.txt
for round in 1 2; do
  for imp in impostor meshes; do
    extra=""; [ $imp = impostor ] && extra="--impostor"
    timeout 150 .gl/live/crowd_bench $common --lods screen --part-lod $extra --error-table-size 10 --scenes field --paths gpu-driven --sizes 100000 --frames 30 --vulkan --gpu-passes --csv $OUT/${imp}_$round.csv > $OUT/${imp}_$round.log 2>&1
    echo "rc $?" >> $OUT/${imp}_$round.log
    echo "== $imp round $round"; grep -A6 "^Vulkan" $OUT/${imp}_$round.log | grep -E "^gpu|GPU ms" | cut -c1-200
  done
done
nvidia-smi --query-gpu=clocks.sm --format=csv,noheader | tee -a $OUT/gpu.txt
