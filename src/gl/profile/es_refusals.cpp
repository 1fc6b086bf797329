// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// What the ES profile refuses by name: the renderer options that need what OpenGL ES 3.0 lacks.
#include "core/str_cat.h"
#include "gl/profile/gl_profile.h"

namespace si::detail {

Status esUnsupported(const char* what, const char* capability) {
  return {StatusCode::kUnsupported, strCat(what, ": the OpenGL ES profile has no ", capability)};
}

Status esRefusesDesc(const RendererDesc& desc) {
  const char* what = "Renderer::init";
  if (desc.skinning_path == SkinningPath::kCompute)
    return esUnsupported(what, "compute shaders (RendererDesc::skinning_path kCompute)");
  if (desc.gpu_occlusion_culling)
    return esUnsupported(what, "compute shaders (RendererDesc::gpu_occlusion_culling)");
  if (desc.motion_vectors)
    return esUnsupported(what, "motion-vector programs (RendererDesc::motion_vectors)");
  if (desc.measure_gpu_time)
    return esUnsupported(what, "timer queries (RendererDesc::measure_gpu_time)");
  if (desc.measure_gpu_passes)
    return esUnsupported(what, "timer queries (RendererDesc::measure_gpu_passes)");
  return Status::ok();
}

}  // namespace si::detail
