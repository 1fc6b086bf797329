// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// What a SPIR-V module declares that a Vulkan pipeline must be given: each descriptor (set,
// binding, kind, name) and the members of its default uniform block (glslang's relaxed rules put
// a shader's loose uniforms there; the back-end names the block and its binding at build time)
// with their offsets; the stage's inputs and outputs by location. Read from the module's own
// decorations, so the pipeline layout follows the shaders as they are compiled. No Vulkan here:
// plain data the back-end maps to Vulkan types.

#include <cstdint>
#include <string>
#include <vector>

#include "si/core/span.h"
#include "si/core/status.h"

namespace si::vk::detail {

/// A descriptor's kind, as Vulkan's VkDescriptorType names it.
enum class DescriptorKind : uint8_t {
  kUniformBuffer = 0,     ///< A uniform block.
  kStorageBuffer,         ///< A shader storage block.
  kCombinedImageSampler,  ///< A GLSL sampler (sampler2D, usampler2D, sampler2DArray ...).
  kUniformTexelBuffer,    ///< A GLSL samplerBuffer.
  kStorageImage,          ///< A GLSL image.
};
const char* descriptorKindName(DescriptorKind kind);

/// One descriptor the module declares.
struct SpirvDescriptor {
  uint32_t set = 0;
  uint32_t binding = 0;
  DescriptorKind kind = DescriptorKind::kUniformBuffer;
  uint32_t count = 1;  ///< Array elements (1 for a single descriptor).
  std::string name;    ///< The block's type name, or the sampler's or image's variable name.
};

/// One member of a uniform block: its name and byte offset, and for an array the bytes from one
/// element to the next (std140 rounds a scalar array's up to 16; 0 for a member that is no
/// array).
struct SpirvMember {
  std::string name;
  uint32_t offset = 0;
  uint32_t array_stride = 0;
};

/// One stage input or output with a location (built-ins have none): its variable's name.
struct SpirvVarying {
  std::string name;
  uint32_t location = 0;
};

/// What reflectSpirv() reads.
struct SpirvReflection {
  std::vector<SpirvDescriptor> descriptors;  ///< In binding order within each set.
  /// The members of the uniform block whose type is named as reflectSpirv()'s `defaults_block`
  /// (empty when the module has none); its descriptor is in `descriptors` too.
  std::vector<SpirvMember> default_uniforms;
  /// The stage's inputs and outputs with a location, in location order: where two stages meet
  /// (Vulkan matches them by location, not by name).
  std::vector<SpirvVarying> inputs, outputs;
};

/// Default-block member `name` of `r`, or null when the stage has none.
const SpirvMember* defaultMember(const SpirvReflection& r, const char* name);
/// Writes `count` values of `size` bytes from `values` into default block `block` at `member`
/// (element k at its array stride); nothing when `member` is null (the stage has none).
void writeDefault(uint8_t* block, const SpirvMember* member, const void* values, size_t size,
                  uint32_t count = 1);
/// The same for member `name` of `r`.
inline void writeDefault(uint8_t* block, const SpirvReflection& r, const char* name,
                         const void* values, size_t size, uint32_t count = 1) {
  writeDefault(block, defaultMember(r, name), values, size, count);
}

/// Reads the descriptors, the default block's members and the located inputs and outputs of
/// SPIR-V module `words`.
/// kInvalidArgument, naming the word, for a module that is not SPIR-V (magic number), an
/// instruction that runs past the end or is shorter than its operands, or a descriptor without
/// a binding; nothing is written to `out` then.
Status reflectSpirv(Span<const uint32_t> words, const char* defaults_block, SpirvReflection* out);

}  // namespace si::vk::detail
