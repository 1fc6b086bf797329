#!/bin/bash
# Device run: the Vulkan render tests and vulkan_host --gpu-driven under the validation layer.
for f in .gl/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.gl/lib:$PWD/.gl/vvl/usr/lib/x86_64-linux-gnu
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export VK_LAYER_PATH=$PWD/.gl/vvl/usr/share/vulkan/explicit_layer.d
export SI_REQUIRE_VULKAN=1 SI_ALL_BACKENDS=1
nvidia-smi --query-gpu=name,driver_version --format=csv | tee $OUT/gpu.txt
for z in "" --reverse-z; do
  timeout 90 .gl/live/vulkan_host --size 1920x1080 --instances 20000 --frames 20 --gpu-driven $z --out $OUT/vulkan_host_gpu_driven$z.png > $OUT/vulkan_host_gpu_driven$z.log 2>&1; echo "rc $?" >> $OUT/vulkan_host_gpu_driven$z.log
  timeout 90 .gl/live/vulkan_host --size 1920x1080 --instances 20000 --frames 20 $z --out /tmp/cpu.png > $OUT/vulkan_host_cpu$z.log 2>&1; echo "rc $?" >> $OUT/vulkan_host_cpu$z.log
done
tail -n 3 $OUT/vulkan_host_*.log
timeout 300 .gl/live/si_vk_render_tests > $OUT/vk_tests.log 2>&1; echo "rc $?" >> $OUT/vk_tests.log
grep -E "^\[  (PASSED|FAILED) |^\[==========\]|rc |FAILED" $OUT/vk_tests.log | head -20
