// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The renderer's motion vectors (RendererDesc::motion_vectors): fragment output 1 gets the
// fragment's screen motion from the previous frame to this one, in texture coordinate units
// (a full viewport is 1): this frame's position minus the previous one, both from the clip
// positions the vertex shader gave under the crowd's last two update cameras, divided per
// fragment. A vertex behind the previous camera (w <= 0) has no previous screen position: 0.
#ifndef SI_MOTION_OUTPUT_GLSL
#define SI_MOTION_OUTPUT_GLSL
in vec4 v_motion_current;
in vec4 v_motion_previous;
layout(location = 1) out vec2 o_motion;
void siWriteMotion() {
  o_motion = v_motion_previous.w > 0.0 && v_motion_current.w > 0.0
                 ? 0.5 * (v_motion_current.xy / v_motion_current.w -
                          v_motion_previous.xy / v_motion_previous.w)
                 : vec2(0.0);
}
#endif
