#!/bin/bash
# Device run: the Vulkan back-end's render test on NVIDIA's driver, the validation layer on.
for f in .gl/*.deb; do dpkg -x $f / >/dev/null; done; ldconfig
export LD_LIBRARY_PATH=$PWD/.gl/lib:$PWD/.gl/vvl/usr/lib/x86_64-linux-gnu
export __EGL_VENDOR_LIBRARY_FILENAMES=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export VK_LAYER_PATH=$PWD/.gl/vvl/usr/share/vulkan/explicit_layer.d
export SI_REQUIRE_VULKAN=1 SI_ALL_BACKENDS=1
nvidia-smi --query-gpu=name,driver_version --format=csv | tee $OUT/gpu.txt
timeout 200 .gl/live/si_vk_render_tests > $OUT/vk.log 2>&1; echo "rc $?" >> $OUT/vk.log
tail -30 $OUT/vk.log
