// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Compiling and linking the catalog's programs, with the driver's log on failure.
#include "gl/programs/program_set.h"

#include <algorithm>

#include "core/str_cat.h"
#include "gl/programs/material_check.h"

namespace si::detail {

namespace {

GLenum glStage(ShaderStage stage) {
  switch (stage) {
    case ShaderStage::kVertex: return GL_VERTEX_SHADER;
    case ShaderStage::kFragment: return GL_FRAGMENT_SHADER;
    case ShaderStage::kCompute: return GL_COMPUTE_SHADER;
  }
  return GL_VERTEX_SHADER;
}

ShaderStage stageOf(GLenum type) {
  return type == GL_VERTEX_SHADER    ? ShaderStage::kVertex
         : type == GL_COMPUTE_SHADER ? ShaderStage::kCompute
                                     : ShaderStage::kFragment;
}

// The driver's log of shader or program `object` (glGetShaderiv / glGetProgramiv and their
// InfoLog functions).
template <class GetIv, class GetLog>
std::string infoLog(GLuint object, GetIv get_iv, GetLog get_log) {
  GLint length = 0;
  get_iv(object, GL_INFO_LOG_LENGTH, &length);
  std::string log(size_t(std::max(length, 1)), '\0');
  get_log(object, length, nullptr, log.data());
  return log;
}

// Checks a linked program: kBackend with the driver's log (and the program deleted) on failure.
Status finishLink(GLuint program, const char* name, GLuint* out) {
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = infoLog(program, glGetProgramiv, glGetProgramInfoLog);
    glDeleteProgram(program);
    return {StatusCode::kBackend, strCat("linking the ", name, " program failed: ", log.c_str())};
  }
  *out = program;
  return Status::ok();
}

Program describe(GLuint id) {
  Program p;
  p.id = id;
  p.view_projection = glGetUniformLocation(id, "u_view_projection");
  p.light_direction = glGetUniformLocation(id, "u_light_direction");
  p.custom_layers = glGetUniformLocation(id, "u_custom_layers");
  p.lod = glGetUniformLocation(id, "u_lod");
  p.motion_view_projection = glGetUniformLocation(id, "u_motion_view_projection");
  p.previous_view_projection = glGetUniformLocation(id, "u_previous_view_projection");
  p.instance_handle = glGetUniformLocation(id, "u_instance_handle");
  p.batch_slot = glGetUniformLocation(id, "u_batch_slot");
  p.impostor_surface = glGetUniformLocation(id, "u_impostor_surface");
  return p;
}

// Compiles every stage of `id` with `material` (null: the built-in one) and links them.
Status buildProgram(ProgramId id, const ShaderConfig& config, const MaterialSource* material,
                    GLuint* out) {
  const ProgramSpec& spec = programSpec(id);
  const GLuint program = glCreateProgram();
  Status s;
  for (ShaderStage stage : {ShaderStage::kVertex, ShaderStage::kFragment, ShaderStage::kCompute}) {
    if (spec.file(stage) == nullptr) continue;
    std::string source;
    s = assembleStage(id, stage, config, &source, material);
    GLuint shader = kNoObject;
    if (s.isOk()) s = compileShader(glStage(stage), source, spec.name, &shader);
    if (!s.isOk()) break;
    glAttachShader(program, shader);
    glDeleteShader(shader);  // Flagged; freed with the program.
  }
  if (!s.isOk()) {
    glDeleteProgram(program);
    return s;
  }
  if (spec.capture_varying != nullptr)
    glTransformFeedbackVaryings(program, 1, &spec.capture_varying, GL_INTERLEAVED_ATTRIBS);
  glLinkProgram(program);
  return finishLink(program, spec.name, out);
}

// GLSL ES 3.00 has no binding qualifiers: the blocks and samplers get the bindings the
// desktop shaders declare (esBindings()) once linked. A name the program lacks is skipped.
void bindEsResources(GLuint program) {
  size_t count = 0;
  const EsBinding* bindings = esBindings(&count);
  for (size_t i = 0; i < count; ++i) {
    const EsBinding& b = bindings[i];
    if (b.sampler) {
      const GLint location = glGetUniformLocation(program, b.name);
      if (location >= 0) glProgramUniform1i(program, location, GLint(b.binding));
    } else {
      const GLuint block = glGetUniformBlockIndex(program, b.name);
      if (block != GL_INVALID_INDEX) glUniformBlockBinding(program, block, b.binding);
    }
  }
}

}  // namespace

Status compileShader(GLenum type, const std::string& source, const char* name, GLuint* out) {
  const GLuint shader = glCreateShader(type);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = infoLog(shader, glGetShaderiv, glGetShaderInfoLog);
    glDeleteShader(shader);
    return {StatusCode::kBackend, strCat("compiling the ", name, " ",
                                         shaderStageName(stageOf(type)),
                                         " shader failed: ", log.c_str())};
  }
  *out = shader;
  return Status::ok();
}

Status ProgramSet::build(const ShaderConfig& config) {
  release();
  config_ = config;
  for (size_t i = 0; i < kProgramCount; ++i) {
    if (config.es && !esProgram(ProgramId(i))) continue;  // Stays kNoObject.
    GLuint id = kNoObject;
    const Status s = buildProgram(ProgramId(i), config, nullptr, &id);
    if (!s.isOk()) {
      release();
      return s;
    }
    if (config.es) bindEsResources(id);
    else bindings_.add(id);
    programs_[i] = describe(id);
  }
  // The instance handles' block and the baselines' uniform (shaders/instance_handle.glsl) are
  // in no built-in program: only the programs of materials that ask for the handle declare them.
  // Nor is the morph targets' texture: only the variants of characters with targets
  // (buildMeshVariants) declare it.
  if (!config.es) {
    bindings_.units[5].insert("si_morphs");
    bindings_.storage_blocks[29].insert("SiSlotHandles");
    bindings_.uniform_names.insert("u_instance_handle");
  }
  return Status::ok();
}

Status ProgramSet::addMaterial(const MaterialSource& material, uint32_t* index) {
  auto m = std::make_unique<MaterialPrograms>();
  m->source = material;
  const auto drop = [&m] {
    for (Program& p : m->programs)
      if (p.id != kNoObject) glDeleteProgram(p.id);
  };
  for (size_t i = 0; i < kProgramCount; ++i) {
    const ProgramId id = ProgramId(i);
    if (programs_[i].id == kNoObject || !takesMaterial(id, material)) continue;
    GLuint program = kNoObject;
    Status s = buildProgram(id, config_, &m->source, &program);
    if (s.isOk()) {
      m->programs[i] = describe(program);
      s = checkMaterialResources(bindings_, program);
    }
    if (!s.isOk()) {
      drop();
      return {s.code(), strCat("material '", material.name, "', ", programSpec(id).name,
                               " program: ", s.message(),
                               s.code() == StatusCode::kBackend
                                   ? " (the material's own lines are numbered from 1, as source "
                                     "string 1 where the driver names source strings)"
                                   : "")};
    }
  }
  materials_.push_back(std::move(m));
  *index = uint32_t(materials_.size());
  return Status::ok();
}

Status ProgramSet::buildMaskedDepth(uint32_t features) {
  MaterialSource mask_only;
  mask_only.name = "alpha mask (depth only)";
  mask_only.text = "void siMaterial(SiSurface surface) {}\n";
  mask_only.depth_discard = true;
  ShaderConfig config = config_;
  config.eight_influences = (features & kMeshEightInfluences) != 0;
  config.morph_targets = (features & kMeshMorphTargets) != 0;
  std::array<Program, kProgramCount>& masked = masked_depth_[features & kMeshSkinFeatures];
  for (size_t i = 0; i < kProgramCount; ++i) {
    const ProgramId id = ProgramId(i);
    if (programs_[i].id == kNoObject || masked[i].id != kNoObject ||
        materialUse(id) != MaterialUse::kDepth)
      continue;
    GLuint program = kNoObject;
    const Status s = buildProgram(id, config, &mask_only, &program);
    if (!s.isOk()) return s;
    if (config_.es) bindEsResources(program);
    masked[i] = describe(program);
  }
  return Status::ok();
}

namespace {
// Whether mesh `features` change program `id`.
bool changedBy(ProgramId id, uint32_t features) {
  return ((features & kMeshVertexWords) != 0 && readsVertexWords(id)) ||
         ((features & kMeshSkinFeatures) != 0 && skinsVertices(id)) ||
         ((features & kMeshMorphTargets) != 0 && composesLayers(id));
}
}  // namespace

Status ProgramSet::buildMeshVariants(uint32_t material, uint32_t features) {
  if (material >= materialCount())
    return {StatusCode::kInvalidArgument, strCat("no material ", material)};
  if (features == 0 || features >= variants_.size()) return Status::ok();
  if (material != 0) {
    const Status s = buildMeshVariants(0, features);  // The programs the material leaves.
    if (!s.isOk()) return s;
  }
  std::vector<std::array<Program, kProgramCount>>& by_material = variants_[features];
  if (by_material.size() <= material) by_material.resize(material + 1);
  const MaterialSource* source = material == 0 ? nullptr : &materials_[material - 1]->source;
  ShaderConfig config = config_;
  config.vertex_words = (features & kMeshVertexWords) != 0;
  config.eight_influences = (features & kMeshEightInfluences) != 0;
  config.morph_targets = (features & kMeshMorphTargets) != 0;
  for (size_t i = 0; i < kProgramCount; ++i) {
    const ProgramId id = ProgramId(i);
    Program& variant = by_material[material][i];
    if (programs_[i].id == kNoObject || variant.id != kNoObject || !changedBy(id, features) ||
        (source != nullptr && !takesMaterial(id, *source)))
      continue;
    GLuint program = kNoObject;
    const Status s = buildProgram(id, config, source, &program);
    if (!s.isOk()) return s;
    if (config_.es) bindEsResources(program);
    variant = describe(program);
  }
  return Status::ok();
}

const Program& ProgramSet::get(ProgramId id, uint32_t material, bool alpha_masked,
                               uint32_t features) const {
  const bool own = material != 0 && material <= materials_.size() &&
                   materials_[material - 1]->programs[size_t(id)].id != kNoObject;
  const Program& masked = masked_depth_[features & kMeshSkinFeatures][size_t(id)];
  // An alpha-masked character's depth-only programs discard by its mask, unless its
  // material's own do.
  if (alpha_masked && !own && masked.id != kNoObject) return masked;
  if (features != 0 && features < variants_.size()) {
    // The material's variant where it changes the program, else the built-in's.
    const std::vector<std::array<Program, kProgramCount>>& by_material = variants_[features];
    const uint32_t m = own ? material : 0;
    if (m < by_material.size() && by_material[m][size_t(id)].id != kNoObject)
      return by_material[m][size_t(id)];
  }
  if (own) return materials_[material - 1]->programs[size_t(id)];
  return programs_[size_t(id)];
}

void ProgramSet::release() {
  bindings_ = LibraryBindings();
  const auto drop = [](std::array<Program, kProgramCount>& set) {
    for (Program& p : set) {
      if (p.id != kNoObject) glDeleteProgram(p.id);
      p = Program();
    }
  };
  drop(programs_);
  for (auto& masked : masked_depth_) drop(masked);
  for (const auto& m : materials_) drop(m->programs);
  materials_.clear();
  for (auto& by_material : variants_) {
    for (auto& variants : by_material) drop(variants);
    by_material.clear();
  }
}

}  // namespace si::detail
