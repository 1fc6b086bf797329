// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Accessors (glTF 2.0 specification, "Accessors", "Sparse accessors"): every range checked
// in 64-bit arithmetic before a byte is read.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "gltf/gltf_convert.h"

namespace si::detail {

namespace {

constexpr uint64_t kMaxElements = uint64_t(1) << 26;  // 67M elements per accessor.

int componentSize(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

double readComponent(const uint8_t* p, int type, bool normalized) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float f;
      std::memcpy(&f, p, 4);
      return f;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? p[0] / 255.0 : p[0];
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const int8_t v = int8_t(p[0]);
      return normalized ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: return 0.0;
  }
}

// The bytes [offset, offset + size) of buffer view `view_index`, checked.
Status viewBytes(const tinygltf::Model& m, int view_index, uint64_t offset, uint64_t size,
                 const std::string& what, const uint8_t** out, uint64_t* view_length) {
  if (view_index < 0 || size_t(view_index) >= m.bufferViews.size())
    return corrupt(strCat(what, ": buffer view ", view_index, " does not exist"));
  const tinygltf::BufferView& v = m.bufferViews[size_t(view_index)];
  if (v.buffer < 0 || size_t(v.buffer) >= m.buffers.size())
    return corrupt(strCat(what, ": buffer view ", view_index, " names buffer ", v.buffer,
                          ", which does not exist"));
  const uint64_t buffer_size = m.buffers[size_t(v.buffer)].data.size();
  const uint64_t begin = uint64_t(v.byteOffset), length = uint64_t(v.byteLength);
  if (begin > buffer_size || length > buffer_size - begin)
    return corrupt(strCat(what, ": buffer view ", view_index, " [", begin, ", +", length,
                          ") lies outside its buffer of ", buffer_size, " bytes"));
  if (offset > length || size > length - offset)
    return corrupt(strCat(what, ": reads [", offset, ", +", size, ") of buffer view ",
                          view_index, ", which has ", length, " bytes"));
  *out = m.buffers[size_t(v.buffer)].data.data() + begin;
  if (view_length) *view_length = length;
  return Status::ok();
}

}  // namespace

Status readAccessor(const tinygltf::Model& m, int index, const std::vector<int>& types,
                    const std::vector<int>& component_types, const std::string& what,
                    std::vector<double>* out, int* components_out) {
  if (index < 0 || size_t(index) >= m.accessors.size())
    return corrupt(strCat(what, ": accessor ", index, " does not exist"));
  const tinygltf::Accessor& a = m.accessors[size_t(index)];
  const std::string name = strCat(what, " (accessor ", index, ")");
  if (std::find(types.begin(), types.end(), a.type) == types.end())
    return corrupt(strCat(name, ": unexpected type ", a.type));
  if (std::find(component_types.begin(), component_types.end(), a.componentType) ==
      component_types.end())
    return corrupt(strCat(name, ": unexpected component type ", a.componentType));
  const int comps = tinygltf::GetNumComponentsInType(uint32_t(a.type));
  const int csize = componentSize(a.componentType);
  if (comps <= 0 || csize <= 0) return corrupt(name + ": invalid type");
  const uint64_t count = a.count;
  if (count > kMaxElements) return corrupt(strCat(name, ": count ", count, " is too large"));
  const uint64_t elem = uint64_t(comps) * uint64_t(csize);
  std::vector<double> values(size_t(count * uint64_t(comps)), 0.0);
  if (a.bufferView >= 0 && count > 0) {
    const tinygltf::BufferView& v = m.bufferViews.size() > size_t(a.bufferView)
                                        ? m.bufferViews[size_t(a.bufferView)]
                                        : tinygltf::BufferView();
    const uint64_t stride = v.byteStride ? uint64_t(v.byteStride) : elem;
    if (stride < elem || stride > 1024)
      return corrupt(strCat(name, ": byte stride ", stride, " does not fit elements of ", elem,
                            " bytes"));
    const uint64_t span = stride * (count - 1) + elem;
    const uint8_t* base = nullptr;
    Status s = viewBytes(m, a.bufferView, uint64_t(a.byteOffset), span, name, &base, nullptr);
    if (!s.isOk()) return s;
    base += a.byteOffset;
    for (uint64_t i = 0; i < count; ++i)
      for (int c = 0; c < comps; ++c)
        values[size_t(i * comps + c)] =
            readComponent(base + i * stride + uint64_t(c) * csize, a.componentType, a.normalized);
  } else if (!a.sparse.isSparse && count > 0) {
    return corrupt(name + ": has neither a buffer view nor sparse values");
  }
  if (a.sparse.isSparse) {
    const uint64_t n = uint64_t(std::max(a.sparse.count, 0));
    if (a.sparse.count <= 0 || n > count)
      return corrupt(strCat(name, ": sparse count ", a.sparse.count, " out of range"));
    const int icomp = a.sparse.indices.componentType;
    const int isize = componentSize(icomp);
    if (icomp != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        icomp != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        icomp != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      return corrupt(name + ": sparse indices must be unsigned integers");
    const uint8_t* ib = nullptr;
    const uint8_t* vb = nullptr;
    if (a.sparse.indices.byteOffset < 0 || a.sparse.values.byteOffset < 0)
      return corrupt(name + ": negative sparse byte offset");
    Status s = viewBytes(m, a.sparse.indices.bufferView, uint64_t(a.sparse.indices.byteOffset),
                         n * uint64_t(isize), name + " sparse indices", &ib, nullptr);
    if (s.isOk())
      s = viewBytes(m, a.sparse.values.bufferView, uint64_t(a.sparse.values.byteOffset), n * elem,
                    name + " sparse values", &vb, nullptr);
    if (!s.isOk()) return s;
    ib += a.sparse.indices.byteOffset;
    vb += a.sparse.values.byteOffset;
    for (uint64_t k = 0; k < n; ++k) {
      const uint64_t target = uint64_t(readComponent(ib + k * isize, icomp, false));
      if (target >= count)
        return corrupt(strCat(name, ": sparse index ", target, " is not below ", count));
      for (int c = 0; c < comps; ++c)
        values[size_t(target * comps + c)] =
            readComponent(vb + k * elem + uint64_t(c) * csize, a.componentType, a.normalized);
    }
  }
  for (double v : values)
    if (!std::isfinite(v)) return corrupt(name + ": contains NaN or infinity");
  if (components_out) *components_out = comps;
  *out = std::move(values);
  return Status::ok();
}

const std::vector<int> kFloat = {TINYGLTF_COMPONENT_TYPE_FLOAT};
const std::vector<int> kAnyInt = {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                  TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                  TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT};
const std::vector<int> kFloatOrNormalized = {
    TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
    TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_COMPONENT_TYPE_BYTE,
    TINYGLTF_COMPONENT_TYPE_SHORT};

}  // namespace si::detail
