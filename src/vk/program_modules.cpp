// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// A program's shader modules and what they declare.
#include "vk/program_modules.h"

#include <utility>

#include "core/str_cat.h"
#include "si_vk/vulkan_profile.h"
#include "vk/device_objects.h"
#include "vk/spirv_modules.h"

namespace si::vk::detail {

using si::detail::strCat;

Status loadProgramModules(VkDevice device, const VkAllocationCallbacks* allocator, const char* name,
                          VkDeviceSize defaults_range, ProgramModules* out) {
  const SpirvModule* vert = findSpirvModule(strCat(name, ".vert").c_str());
  const SpirvModule* frag = findSpirvModule(strCat(name, ".frag").c_str());
  if (vert == nullptr || frag == nullptr)
    return {StatusCode::kNotFound, strCat("the ", name, " program's SPIR-V is not embedded")};
  Status s = reflectSpirv(Span<const uint32_t>(vert->words, vert->word_count), kDefaultUniformBlock,
                          &out->vertex_reflection);
  if (s.isOk())
    s = reflectSpirv(Span<const uint32_t>(frag->words, frag->word_count), kDefaultUniformBlock,
                     &out->fragment_reflection);
  // Every default member within its block's range (the largest a 4x4 matrix).
  for (const SpirvReflection* r : {&out->vertex_reflection, &out->fragment_reflection})
    for (const SpirvMember& member : r->default_uniforms)
      if (s.isOk() && member.offset + 64 > defaults_range)
        s = {StatusCode::kUnsupported,
             strCat("the ", name, " program's default uniform '", member.name, "' at byte ",
                    member.offset, " passes the ", defaults_range, " bytes the renderer gives it")};
  for (const auto& [module, made] :
       {std::pair{vert, &out->vertex_module}, std::pair{frag, &out->fragment_module}}) {
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
  for (VkShaderModule* module : {&p->vertex_module, &p->fragment_module}) {
    if (*module != VK_NULL_HANDLE) vkDestroyShaderModule(device, *module, allocator);
    *module = VK_NULL_HANDLE;
  }
}

}  // namespace si::vk::detail
