// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// A host material's resources checked against the library's bindings.
#include "gl/programs/material_check.h"

#include <string>
#include <vector>

#include "core/str_cat.h"

namespace si::detail {

namespace {

bool isSampler(GLenum type) {
  switch (type) {
    case GL_SAMPLER_1D: case GL_SAMPLER_2D: case GL_SAMPLER_3D: case GL_SAMPLER_CUBE:
    case GL_SAMPLER_1D_SHADOW: case GL_SAMPLER_2D_SHADOW: case GL_SAMPLER_1D_ARRAY:
    case GL_SAMPLER_2D_ARRAY: case GL_SAMPLER_1D_ARRAY_SHADOW: case GL_SAMPLER_2D_ARRAY_SHADOW:
    case GL_SAMPLER_2D_MULTISAMPLE: case GL_SAMPLER_2D_MULTISAMPLE_ARRAY:
    case GL_SAMPLER_CUBE_SHADOW: case GL_SAMPLER_BUFFER: case GL_SAMPLER_2D_RECT:
    case GL_SAMPLER_2D_RECT_SHADOW: case GL_SAMPLER_CUBE_MAP_ARRAY:
    case GL_SAMPLER_CUBE_MAP_ARRAY_SHADOW: case GL_INT_SAMPLER_1D: case GL_INT_SAMPLER_2D:
    case GL_INT_SAMPLER_3D: case GL_INT_SAMPLER_CUBE: case GL_INT_SAMPLER_1D_ARRAY:
    case GL_INT_SAMPLER_2D_ARRAY: case GL_INT_SAMPLER_2D_MULTISAMPLE:
    case GL_INT_SAMPLER_2D_MULTISAMPLE_ARRAY: case GL_INT_SAMPLER_BUFFER:
    case GL_INT_SAMPLER_2D_RECT: case GL_INT_SAMPLER_CUBE_MAP_ARRAY:
    case GL_UNSIGNED_INT_SAMPLER_1D: case GL_UNSIGNED_INT_SAMPLER_2D:
    case GL_UNSIGNED_INT_SAMPLER_3D: case GL_UNSIGNED_INT_SAMPLER_CUBE:
    case GL_UNSIGNED_INT_SAMPLER_1D_ARRAY: case GL_UNSIGNED_INT_SAMPLER_2D_ARRAY:
    case GL_UNSIGNED_INT_SAMPLER_2D_MULTISAMPLE:
    case GL_UNSIGNED_INT_SAMPLER_2D_MULTISAMPLE_ARRAY: case GL_UNSIGNED_INT_SAMPLER_BUFFER:
    case GL_UNSIGNED_INT_SAMPLER_2D_RECT: case GL_UNSIGNED_INT_SAMPLER_CUBE_MAP_ARRAY:
      return true;
    default:
      return false;
  }
}

// GL_IMAGE_1D to GL_UNSIGNED_INT_IMAGE_2D_MULTISAMPLE_ARRAY are one range of enums.
bool isImage(GLenum type) {
  return type >= GL_IMAGE_1D && type <= GL_UNSIGNED_INT_IMAGE_2D_MULTISAMPLE_ARRAY;
}

// One active resource: its name, and its texture unit, image unit or binding (-1 for a loose
// uniform).
struct Resource {
  std::string name;
  GLint binding = -1;
  bool sampler = false, image = false;
};

std::string resourceName(GLuint program, GLenum interface, GLuint index) {
  GLint length = 0;
  const GLenum property = GL_NAME_LENGTH;
  glGetProgramResourceiv(program, interface, index, 1, &property, 1, nullptr, &length);
  std::string name(size_t(length > 0 ? length : 1), '\0');
  glGetProgramResourceName(program, interface, index, GLsizei(name.size()), nullptr, name.data());
  name.resize(name.find('\0') == std::string::npos ? name.size() : name.find('\0'));
  return name;
}

// The default-block uniforms of `program` (samplers with their units; array samplers give
// their first element's unit).
std::vector<Resource> defaultUniforms(GLuint program) {
  std::vector<Resource> out;
  GLint count = 0;
  glGetProgramInterfaceiv(program, GL_UNIFORM, GL_ACTIVE_RESOURCES, &count);
  for (GLint i = 0; i < count; ++i) {
    const GLenum properties[] = {GL_BLOCK_INDEX, GL_TYPE, GL_LOCATION};
    GLint values[3] = {-1, 0, -1};
    glGetProgramResourceiv(program, GL_UNIFORM, GLuint(i), 3, properties, 3, nullptr, values);
    if (values[0] != -1) continue;  // In a block.
    Resource r;
    r.name = resourceName(program, GL_UNIFORM, GLuint(i));
    r.sampler = isSampler(GLenum(values[1]));
    r.image = isImage(GLenum(values[1]));
    if ((r.sampler || r.image) && values[2] >= 0) glGetUniformiv(program, values[2], &r.binding);
    out.push_back(r);
  }
  return out;
}

// The blocks of `interface` (GL_UNIFORM_BLOCK, GL_SHADER_STORAGE_BLOCK) with their bindings.
std::vector<Resource> blocks(GLuint program, GLenum interface) {
  std::vector<Resource> out;
  GLint count = 0;
  glGetProgramInterfaceiv(program, interface, GL_ACTIVE_RESOURCES, &count);
  for (GLint i = 0; i < count; ++i) {
    Resource r;
    r.name = resourceName(program, interface, GLuint(i));
    const GLenum property = GL_BUFFER_BINDING;
    glGetProgramResourceiv(program, interface, GLuint(i), 1, &property, 1, nullptr, &r.binding);
    out.push_back(r);
  }
  return out;
}

// kInvalidArgument when a resource of `material`'s list that is not the library's own resource
// there sits at a binding in `taken` (the library's resources of that kind).
Status checkBindings(const std::map<GLint, std::set<std::string>>& taken,
                     const std::vector<Resource>& material, const char* kind,
                     const char* binding_word) {
  for (const Resource& r : material) {
    const auto found = taken.find(r.binding);
    if (r.binding >= 0 && found != taken.end() && found->second.count(r.name) == 0)
      return {StatusCode::kInvalidArgument,
              strCat(kind, " '", r.name, "' is at ", binding_word, " ", r.binding,
                     ", where the library's draws bind their own '", *found->second.begin(),
                     "'; give it another (docs/rendering.md, \"Materials\", lists the "
                     "library's)")};
  }
  return Status::ok();
}

std::vector<Resource> samplers(const std::vector<Resource>& uniforms, bool images) {
  std::vector<Resource> out;
  for (const Resource& r : uniforms)
    if (images ? r.image : r.sampler) out.push_back(r);
  return out;
}

}  // namespace

void LibraryBindings::add(GLuint program) {
  for (const Resource& r : defaultUniforms(program)) {
    uniform_names.insert(r.name);
    if (r.sampler && r.binding >= 0) units[r.binding].insert(r.name);
    if (r.image && r.binding >= 0) images[r.binding].insert(r.name);
  }
  for (const Resource& r : blocks(program, GL_UNIFORM_BLOCK))
    uniform_blocks[r.binding].insert(r.name);
  for (const Resource& r : blocks(program, GL_SHADER_STORAGE_BLOCK))
    storage_blocks[r.binding].insert(r.name);
}

Status checkMaterialResources(const LibraryBindings& library, GLuint material) {
  const std::vector<Resource> uniforms = defaultUniforms(material);
  for (const Resource& r : uniforms)
    if (!r.sampler && !r.image && library.uniform_names.count(r.name) == 0)
      return {StatusCode::kInvalidArgument,
              strCat("uniform '", r.name, "' is a loose uniform, which nothing can set (the "
                     "program is the library's); put it in a uniform block at a binding of the "
                     "material's own")};
  Status s = checkBindings(library.units, samplers(uniforms, false), "sampler", "texture unit");
  if (s.isOk())
    s = checkBindings(library.images, samplers(uniforms, true), "image", "image unit");
  if (s.isOk())
    s = checkBindings(library.uniform_blocks, blocks(material, GL_UNIFORM_BLOCK), "uniform block",
                      "uniform buffer binding");
  if (s.isOk())
    s = checkBindings(library.storage_blocks, blocks(material, GL_SHADER_STORAGE_BLOCK),
                      "storage block", "shader storage binding");
  return s;
}

}  // namespace si::detail
