#!/bin/bash
# Device run: where si::vk's and si::gl's GPU time goes on the GPU-driven path (crowd_bench
# --vulkan --gpu-passes: GL's per-pass timers, Vulkan's timestamp after its passes), the impostor
# field at 100k and 1M, round $1, beside the same run without --gpu-passes; with "tests" as $2
# the Vulkan layers and GPU-driven render tests with the validation layer.
for f in .gl/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.gl/lib:$PWD/.gl/vvl/usr/lib/x86_64-linux-gnu
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
nvidia-smi --query-gpu=name,driver_version --format=csv | tee $OUT/gpu.txt
common="--quick --backend egl-device --size 1920x1080 --quality-budgets none"
timeout 60 .gl/live/crowd_bench $common --lods distance --error-table-size 0 --scenes field --paths instanced --sizes 100000 --frames 40 --csv /tmp/w.csv > /tmp/warm.log 2>&1
nvidia-smi --query-gpu=clocks.sm --format=csv,noheader | tee -a $OUT/gpu.txt
round=$1
for mode in passes plain; do
  extra=""; [ $mode = passes ] && extra="--gpu-passes"
  timeout 200 .gl/live/crowd_bench $common --lods screen --part-lod --impostor --error-table-size 10 --scenes field --paths gpu-driven,gpu-driven-occlusion --sizes 100000,1000000 --frames 20 --vulkan $extra --csv $OUT/${mode}_$round.csv > $OUT/${mode}_$round.log 2>&1
  echo "rc $?" >> $OUT/${mode}_$round.log
  grep -A12 "^Vulkan" $OUT/${mode}_$round.log | grep -E "GL|Vulkan|GPU ms"
done
nvidia-smi --query-gpu=clocks.sm --format=csv,noheader | tee -a $OUT/gpu.txt
if [ "$2" = tests ]; then
  export VK_LAYER_PATH=$PWD/.gl/vvl/usr/share/vulkan/explicit_layer.d
  export SI_REQUIRE_VULKAN=1 SI_ALL_BACKENDS=1
  timeout 200 .gl/live/si_vk_render_tests --gtest_filter="*Layers*:*GpuDriven*" > $OUT/vk_tests.log 2>&1; echo "rc $?" >> $OUT/vk_tests.log
  grep -E "^\[  (PASSED|FAILED) |^\[==========\]|rc |FAILED|motion \]|layers \]" $OUT/vk_tests.log | head -30
fi
