// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// si::skinningGlsl(): the public include (shaders/si_skinning.glsl), embedded with its includes
// expanded. The GLSL twin of si::emulateSkinningMatrix / si::emulateSkinning.
#include "si/gl/skinning_glsl.h"

#include "gl/programs/embedded_shaders.h"

namespace si {

const char* skinningGlsl() {
  const char* source = detail::embeddedShader("si_skinning.glsl");
  return source != nullptr ? source : "#error si_skinning.glsl was not embedded\n";
}

}  // namespace si
