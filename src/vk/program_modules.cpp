// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// A program's shader modules and what they declare.
#include "vk/program_modules.h"

#include <vector>

#include "core/str_cat.h"
#include "si_vk/vulkan_profile.h"
#include "vk/device_objects.h"
#include "vk/spirv_modules.h"

namespace si::vk::detail {

using si::detail::strCat;

Status loadProgramModules(VkDevice device, const VkAllocationCallbacks* allocator, const char* name,
                          bool compute, VkDeviceSize defaults_range, ProgramModules* out) {
  struct Stage {
    const SpirvModule* module;
    SpirvReflection* reflection;
    VkShaderModule* made;
  };
  std::vector<Stage> stages;
  if (compute) {
    stages.push_back({findSpirvModule(strCat(name, ".comp").c_str()), &out->compute_reflection,
                      &out->compute_module});
  } else {
    stages.push_back({findSpirvModule(strCat(name, ".vert").c_str()), &out->vertex_reflection,
                      &out->vertex_module});
    stages.push_back({findSpirvModule(strCat(name, ".frag").c_str()), &out->fragment_reflection,
                      &out->fragment_module});
  }
  for (const Stage& stage : stages)
    if (stage.module == nullptr)
      return {StatusCode::kNotFound, strCat("the ", name, " program's SPIR-V is not embedded")};
  Status s = Status::ok();
  for (const Stage& stage : stages)
    if (s.isOk())
      s = reflectSpirv(Span<const uint32_t>(stage.module->words, stage.module->word_count),
                       kDefaultUniformBlock, stage.reflection);
  // Every default member within its block's range (the largest a 4x4 matrix).
  for (const Stage& stage : stages)
    for (const SpirvMember& member : stage.reflection->default_uniforms)
      if (s.isOk() && member.offset + 64 > defaults_range)
        s = {StatusCode::kUnsupported,
             strCat("the ", name, " program's default uniform '", member.name, "' at byte ",
                    member.offset, " passes the ", defaults_range, " bytes the renderer gives it")};
  for (const Stage& stage : stages) {
    const SpirvModule* module = stage.module;
    VkShaderModule* made = stage.made;
    if (!s.isOk()) break;
    auto info = vkStruct<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
    info.codeSize = module->word_count * 4;
    info.pCode = module->words;
    s = checkVk(vkCreateShaderModule(device, &info, allocator, made), "vkCreateShaderModule");
  }
  return s;
}

void destroyProgramModules(VkDevice device, const VkAllocationCallbacks* allocator,
                           ProgramModules* p) {
  for (VkShaderModule* module : {&p->vertex_module, &p->fragment_module, &p->compute_module}) {
    if (*module != VK_NULL_HANDLE) vkDestroyShaderModule(device, *module, allocator);
    *module = VK_NULL_HANDLE;
  }
}

}  // namespace si::vk::detail
