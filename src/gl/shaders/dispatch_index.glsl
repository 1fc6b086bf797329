// SkinnedInstancing - SPDX-License-Identifier: MIT (see LICENSE)
// The flat index of this invocation in a dispatch of 64-wide groups laid out as rows
// (src/gl/paths/dispatch_grid.h: rows of at most GL_MAX_COMPUTE_WORK_GROUP_COUNT's x), so a pass
// covers more than 65535 groups. Invocations past the pass's count return early.
#ifndef SI_DISPATCH_INDEX_GLSL
#define SI_DISPATCH_INDEX_GLSL
uint siFlatInvocation() {
  return (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * 64u +
         gl_LocalInvocationIndex;
}
#endif
