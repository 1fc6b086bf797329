#!/bin/bash
# Device run: the Vulkan render tests (depth conventions, motion vectors, 8 influences, vertex
# words, layers) on NVIDIA's driver with the validation layer on, and the vulkan_host example.
for f in .gl/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.gl/lib:$PWD/.gl/vvl/usr/lib/x86_64-linux-gnu
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export VK_LAYER_PATH=$PWD/.gl/vvl/usr/share/vulkan/explicit_layer.d
export SI_REQUIRE_VULKAN=1 SI_ALL_BACKENDS=1
nvidia-smi --query-gpu=name,driver_version --format=csv | tee $OUT/gpu.txt
timeout 300 .gl/live/si_vk_render_tests > $OUT/vk_tests.log 2>&1; echo "rc $?" >> $OUT/vk_tests.log
grep -E "^\[  (PASSED|FAILED) |^\[==========\]|rc |motion \]" $OUT/vk_tests.log
for z in "" --reverse-z; do
  timeout 60 .gl/live/vulkan_host --size 1920x1080 --instances 20000 --frames 10 $z --out $OUT/vulkan_host$z.png > $OUT/vulkan_host$z.log 2>&1; echo "rc $?" >> $OUT/vulkan_host$z.log
  cat $OUT/vulkan_host$z.log
done
