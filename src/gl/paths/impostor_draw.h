// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Drawing a character's impostors (si/gl/impostor.h): the instanced paths' batches at the
// crowd's impostor level, one quad per record; and the GPU-driven path's impostor bucket
// through an indirect command its command pass wrote.

#include "gl/paths/draw_path.h"

namespace si::detail {

/// The batches of `f` at LOD `f.impostor_lod` (sub-mesh 0's; CrowdDesc::impostor_lod puts each
/// instance there once), drawn as impostor quads (glDrawArraysInstanced, 4 vertices, a strip),
/// depth only when `depth_only`. Nothing when the frame has no impostor level.
void drawImpostorBatches(const DrawResources& r, const PathFrame& f, bool depth_only,
                         DrawStats* st);

/// The GPU-driven path's impostors: the impostor quads pass (each quad computed once and, on
/// a single-sampled target, appended into `quads` only where it holds a pixel centre; dispatched
/// by the words at byte `dispatch` of the bound GL_DISPATCH_INDIRECT_BUFFER; reading the
/// counters, records, entries and visible list at storage bindings 3 to 6 and counting into
/// the commands at 7), then glDrawArraysIndirect of the command at byte `command` of the bound
/// GL_DRAW_INDIRECT_BUFFER, with the path's vertex array `vao` bound.
void drawImpostorsIndirect(const DrawResources& r, const PathFrame& f, GLuint vao, GLuint quads,
                           GLintptr dispatch, GLintptr command, DrawStats* st);

}  // namespace si::detail
