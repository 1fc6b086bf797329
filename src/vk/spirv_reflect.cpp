// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Reading a SPIR-V module's descriptors, default uniform block and located inputs and outputs.
#include "vk/spirv_reflect.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <set>

#include "core/str_cat.h"

namespace si::vk::detail {
namespace {

using si::detail::strCat;

// The SPIR-V specification's numbers (unified1/spirv.core.grammar.json).
constexpr uint32_t kMagic = 0x07230203u;
constexpr uint32_t kOpName = 5, kOpMemberName = 6, kOpFunction = 54, kOpTypeImage = 25,
                   kOpTypeSampledImage = 27, kOpTypeArray = 28, kOpTypeStruct = 30,
                   kOpTypePointer = 32, kOpConstant = 43, kOpVariable = 59, kOpDecorate = 71,
                   kOpMemberDecorate = 72;
constexpr uint32_t kDecorationBlock = 2, kDecorationBufferBlock = 3, kDecorationArrayStride = 6,
                   kDecorationBinding = 33, kDecorationDescriptorSet = 34, kDecorationOffset = 35,
                   kDecorationLocation = 30;
constexpr uint32_t kStorageUniformConstant = 0, kStorageInput = 1, kStorageUniform = 2,
                   kStorageOutput = 3, kStorageStorageBuffer = 12;
constexpr uint32_t kDimBuffer = 5;

// A literal string's operand words from `at` (nul-terminated, packed 4 bytes a word).
std::string literalString(Span<const uint32_t> words, size_t at, size_t end) {
  std::string s;
  for (size_t w = at; w < end; ++w)
    for (int b = 0; b < 4; ++b) {
      const char c = char((words[w] >> (8 * b)) & 0xFFu);
      if (c == '\0') return s;
      s.push_back(c);
    }
  return s;
}

// The fewest words an instruction this reader reads has (its opcode word included); 0 for the
// others, which it skips.
uint32_t minimalWordCount(uint32_t opcode) {
  switch (opcode) {
    case kOpName:
      return 3;
    case kOpMemberName:
      return 4;
    case kOpDecorate:
      return 3;
    case kOpMemberDecorate:
      return 4;
    case kOpConstant:
      return 4;
    case kOpVariable:
      return 4;
    case kOpTypeImage:
      return 9;
    case kOpTypeSampledImage:
      return 3;
    case kOpTypeArray:
      return 4;
    case kOpTypeStruct:
      return 2;
    case kOpTypePointer:
      return 4;
    default:
      return 0;
  }
}

struct Type {
  uint32_t opcode = 0;
  std::vector<uint32_t> operands;  // After the result id.
};

}  // namespace

const char* descriptorKindName(DescriptorKind kind) {
  switch (kind) {
    case DescriptorKind::kUniformBuffer:
      return "uniform buffer";
    case DescriptorKind::kStorageBuffer:
      return "storage buffer";
    case DescriptorKind::kCombinedImageSampler:
      return "combined image sampler";
    case DescriptorKind::kUniformTexelBuffer:
      return "uniform texel buffer";
    case DescriptorKind::kStorageImage:
      return "storage image";
  }
  return "unknown";
}

const SpirvMember* defaultMember(const SpirvReflection& r, const char* name) {
  for (const SpirvMember& m : r.default_uniforms)
    if (m.name == name) return &m;
  return nullptr;
}

void writeDefault(uint8_t* block, const SpirvMember* member, const void* values, size_t size,
                  uint32_t count) {
  if (member == nullptr) return;
  const size_t stride = member->array_stride != 0 ? member->array_stride : size;
  for (uint32_t k = 0; k < count; ++k)
    std::memcpy(block + member->offset + k * stride, static_cast<const uint8_t*>(values) + k * size,
                size);
}

Status reflectSpirv(Span<const uint32_t> words, const char* defaults_block, SpirvReflection* out) {
  if (out == nullptr) return {StatusCode::kInvalidArgument, "reflectSpirv: null output"};
  if (words.size() < 5 || words[0] != kMagic)
    return {StatusCode::kInvalidArgument, "reflectSpirv: not a SPIR-V module (no magic number)"};
  std::map<uint32_t, std::string> names;
  std::map<std::pair<uint32_t, uint32_t>, std::string> member_names;
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> member_offsets;
  std::map<uint32_t, uint32_t> bindings, sets, constants, locations, array_strides;
  std::map<uint32_t, uint32_t> block_kind;  // Struct id -> kDecorationBlock or BufferBlock.
  std::map<uint32_t, Type> types;
  struct Variable {
    uint32_t id, pointer, storage;
  };
  std::vector<Variable> variables;
  // Every id an instruction of a function names: a descriptor no instruction uses (declared
  // only: glslang keeps such blocks, and lists them among the entry point's interface) is not
  // statically used, and needs no place in the pipeline layout. A literal operand that happens
  // to equal a variable's id keeps that variable: a layout with one binding more, never less.
  bool in_functions = false;
  std::set<uint32_t> used;
  for (size_t at = 5; at < words.size();) {
    const uint32_t count = words[at] >> 16, opcode = words[at] & 0xFFFFu;
    if (count == 0 || at + count > words.size())
      return {StatusCode::kInvalidArgument,
              strCat("reflectSpirv: the instruction at word ", at, " runs past the module's end")};
    const size_t end = at + count;
    if (count < minimalWordCount(opcode))
      return {StatusCode::kInvalidArgument, strCat("reflectSpirv: the instruction at word ", at,
                                                   " is shorter than its operands")};
    const auto op = [&](uint32_t k) { return words[at + k]; };  // Operand k (from 1).
    in_functions = in_functions || opcode == kOpFunction;
    if (in_functions) used.insert(words.begin() + at + 1, words.begin() + end);
    switch (opcode) {
      case kOpName:
        names[op(1)] = literalString(words, at + 2, end);
        break;
      case kOpMemberName:
        member_names[{op(1), op(2)}] = literalString(words, at + 3, end);
        break;
      case kOpDecorate:
        if (op(2) == kDecorationBinding && count >= 4) bindings[op(1)] = op(3);
        if (op(2) == kDecorationDescriptorSet && count >= 4) sets[op(1)] = op(3);
        if (op(2) == kDecorationLocation && count >= 4) locations[op(1)] = op(3);
        if (op(2) == kDecorationArrayStride && count >= 4) array_strides[op(1)] = op(3);
        if (op(2) == kDecorationBlock || op(2) == kDecorationBufferBlock) block_kind[op(1)] = op(2);
        break;
      case kOpMemberDecorate:
        if (op(3) == kDecorationOffset && count >= 5) member_offsets[{op(1), op(2)}] = op(4);
        break;
      case kOpConstant:
        constants[op(2)] = op(3);
        break;
      case kOpVariable:
        variables.push_back({op(2), op(1), op(3)});
        break;
      case kOpTypeImage:
      case kOpTypeSampledImage:
      case kOpTypeArray:
      case kOpTypeStruct:
      case kOpTypePointer: {
        Type t;
        t.opcode = opcode;
        t.operands.assign(words.begin() + at + 2, words.begin() + end);
        types[op(1)] = std::move(t);
        break;
      }
      default:
        break;
    }
    at = end;
  }
  SpirvReflection r;
  for (const Variable& v : variables) {
    const auto location = locations.find(v.id);
    if ((v.storage == kStorageInput || v.storage == kStorageOutput) && location != locations.end())
      (v.storage == kStorageInput ? r.inputs : r.outputs)
          .push_back({names[v.id], location->second});
    if (v.storage != kStorageUniformConstant && v.storage != kStorageUniform &&
        v.storage != kStorageStorageBuffer)
      continue;
    if (used.count(v.id) == 0) continue;  // Declared, never used.
    const auto pointer = types.find(v.pointer);
    if (pointer == types.end() || pointer->second.operands.size() < 2) continue;
    uint32_t pointee = pointer->second.operands[1], elements = 1;
    const auto array = types.find(pointee);
    if (array != types.end() && array->second.opcode == kOpTypeArray &&
        array->second.operands.size() >= 2) {
      const auto length = constants.find(array->second.operands[1]);
      elements = length != constants.end() ? length->second : 1;
      pointee = array->second.operands[0];
    }
    const auto type = types.find(pointee);
    if (type == types.end()) continue;
    SpirvDescriptor d;
    d.count = elements;
    if (type->second.opcode == kOpTypeStruct) {
      const auto block = block_kind.find(pointee);
      if (block == block_kind.end()) continue;
      d.kind = v.storage == kStorageStorageBuffer || block->second == kDecorationBufferBlock
                   ? DescriptorKind::kStorageBuffer
                   : DescriptorKind::kUniformBuffer;
      d.name = names[pointee];
      if (defaults_block != nullptr && d.name == defaults_block)
        for (uint32_t m = 0; member_names.count({pointee, m}) != 0; ++m) {
          // The member's type (the struct's operand m): an array's stride is decorated there.
          const std::vector<uint32_t>& members = type->second.operands;
          const auto stride =
              m < members.size() ? array_strides.find(members[m]) : array_strides.end();
          r.default_uniforms.push_back({member_names[{pointee, m}], member_offsets[{pointee, m}],
                                        stride != array_strides.end() ? stride->second : 0u});
        }
    } else {
      // A sampler: the sampled image's image (a buffer dimension: a texel buffer); an image.
      uint32_t image = pointee;
      if (type->second.opcode == kOpTypeSampledImage && !type->second.operands.empty())
        image = type->second.operands[0];
      const auto image_type = types.find(image);
      if (image_type == types.end() || image_type->second.opcode != kOpTypeImage ||
          image_type->second.operands.size() < 6)
        continue;
      const bool buffer = image_type->second.operands[1] == kDimBuffer;
      const bool storage = image_type->second.operands[5] == 2;  // Sampled 2: a storage image.
      d.kind = storage  ? DescriptorKind::kStorageImage
               : buffer ? DescriptorKind::kUniformTexelBuffer
                        : DescriptorKind::kCombinedImageSampler;
      d.name = names[v.id];
    }
    const auto binding = bindings.find(v.id);
    if (binding == bindings.end())
      return {StatusCode::kInvalidArgument,
              strCat("reflectSpirv: descriptor '", d.name, "' has no binding")};
    d.binding = binding->second;
    d.set = sets.count(v.id) != 0 ? sets[v.id] : 0;
    r.descriptors.push_back(std::move(d));
  }
  std::sort(r.descriptors.begin(), r.descriptors.end(),
            [](const SpirvDescriptor& a, const SpirvDescriptor& b) {
              return a.set != b.set ? a.set < b.set : a.binding < b.binding;
            });
  for (auto* varyings : {&r.inputs, &r.outputs})
    std::sort(varyings->begin(), varyings->end(),
              [](const SpirvVarying& a, const SpirvVarying& b) { return a.location < b.location; });
  *out = std::move(r);
  return Status::ok();
}

}  // namespace si::vk::detail
