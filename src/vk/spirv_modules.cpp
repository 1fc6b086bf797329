// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Finding an embedded SPIR-V module by name.
#include "vk/spirv_modules.h"

#include <cstring>

namespace si::vk::detail {

const SpirvModule* findSpirvModule(const char* name) {
  for (size_t k = 0; k < kSpirvModuleCount; ++k)
    if (std::strcmp(kSpirvModules[k].name, name) == 0) return &kSpirvModules[k];
  return nullptr;
}

}  // namespace si::vk::detail
