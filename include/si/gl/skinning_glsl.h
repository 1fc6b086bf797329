// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The GLSL skinning code, shipped as a string to put into your own vertex shaders. It declares
/// the instance record (si/crowd/instance_record.h, the one definition of the layout), the
/// instance uniform block, the palette sampler and functions that fetch, interpolate, crossfade
/// and blend the bone matrices exactly as si::emulateSkinningMatrix() and si::emulateSkinning()
/// do on the CPU.
///
/// Usage (GLSL 4.50 core):
/// \code
///   std::string vs = "#version 450 core\n#define SI_MAX_INSTANCES 819\n";
///   vs += si::skinningGlsl();
///   vs += R"(
///     layout(location = 0) in vec3 a_position;
///     layout(location = 3) in uvec4 a_joints;   // palette slots (BakedPalette::skeleton_to_palette)
///     layout(location = 4) in vec4 a_weights;
///     layout(location = 1) uniform mat4 u_view_projection;  // camera-relative
///     void main() {
///       SiInstance inst = si_instances[gl_InstanceID];
///       vec4 m0, m1, m2;
///       siSkin(inst, a_joints, a_weights, m0, m1, m2);
///       vec3 model = siTransformPoint(m0, m1, m2, a_position);
///       vec3 world = siTransformPoint(inst.world_rows[0], inst.world_rows[1], inst.world_rows[2], model);
///       gl_Position = u_view_projection * vec4(world, 1.0);
///     })";
/// \endcode
/// Bindings: the instance block at uniform buffer binding 0, the palette texture at texture
/// unit 0, and `uniform uvec4 si_palette_info` at location 0 (x: log2 of the palette width,
/// y: joint stride in texels, z: 0 for matrix formats, 1 for quaternion + translation).

namespace si {

/// The GLSL source described above (needs SI_MAX_INSTANCES defined before it).
const char* skinningGlsl();

}  // namespace si
