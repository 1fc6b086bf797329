#!/bin/bash
# Device run: the Vulkan render tests with the validation layer (both EGL back-ends), and
# vulkan_host --occlusion at 1920x1080.
for f in .gl/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.gl/lib:$PWD/.gl/vvl/usr/lib/x86_64-linux-gnu
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export VK_LAYER_PATH=$PWD/.gl/vvl/usr/share/vulkan/explicit_layer.d
nvidia-smi --query-gpu=name,driver_version --format=csv | tee $OUT/gpu.txt
export SI_REQUIRE_VULKAN=1 SI_ALL_BACKENDS=1
timeout 400 .gl/live/si_vk_render_tests > $OUT/vk_tests.log 2>&1; echo "rc $?" >> $OUT/vk_tests.log
grep -E "^\[  (PASSED|FAILED) |^\[==========\]|rc |FAILED|occlusion\] (4x|OpenGL) frame 3|motion \]" $OUT/vk_tests.log | head -30
for a in "--gpu-driven" "--occlusion"; do
  timeout 60 .gl/live/vulkan_host --size 1920x1080 --instances 20000 --frames 30 $a --out $OUT/vh$a.png > $OUT/vulkan_host$a.log 2>&1; echo "rc $?" >> $OUT/vulkan_host$a.log
  tail -3 $OUT/vulkan_host$a.log
done
