#!/bin/bash
# Device run: si::vk's GPU-driven path with and without occlusion culling against si::gl's
# (crowd_bench --vulkan, field and plaza, 100k and 1M), round $1; with "tests" as $2 also the
# Vulkan render tests (impostors) with the validation layer.
for f in .gl/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.gl/lib:$PWD/.gl/vvl/usr/lib/x86_64-linux-gnu
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
nvidia-smi --query-gpu=name,driver_version --format=csv | tee $OUT/gpu.txt
common="--quick --backend egl-device --size 1920x1080 --quality-budgets none"
timeout 60 .gl/live/crowd_bench $common --lods distance --error-table-size 0 --scenes field --paths instanced --sizes 100000 --frames 40 --csv /tmp/w.csv > /tmp/warm.log 2>&1
nvidia-smi --query-gpu=clocks.sm --format=csv,noheader | tee -a $OUT/gpu.txt
round=$1
timeout 420 .gl/live/crowd_bench $common --lods screen --part-lod --impostor --error-table-size 10 --scenes field --paths gpu-driven,gpu-driven-occlusion --sizes 100000,1000000 --frames 20 --vulkan --csv $OUT/imp_$round.csv > $OUT/imp_$round.log 2>&1
echo "rc $?" >> $OUT/imp_$round.log
nvidia-smi --query-gpu=clocks.sm --format=csv,noheader | tee -a $OUT/gpu.txt
grep -A8 "^Vulkan" $OUT/imp_$round.log
if [ "$2" = tests ]; then
  export VK_LAYER_PATH=$PWD/.gl/vvl/usr/share/vulkan/explicit_layer.d
  export SI_REQUIRE_VULKAN=1 SI_ALL_BACKENDS=1
  timeout 330 .gl/live/si_vk_render_tests --gtest_filter="*Impostor*:*GpuDriven*" > $OUT/vk_tests.log 2>&1; echo "rc $?" >> $OUT/vk_tests.log
  grep -E "^\[  (PASSED|FAILED) |^\[==========\]|rc |FAILED|occlusion\]" $OUT/vk_tests.log | head -30
fi
