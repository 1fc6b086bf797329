// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Which GL the entry points were loaded for: desktop OpenGL 4.5 core, or OpenGL ES 3.0 and later
// (WebGL 2 included) — the ES profile (docs/rendering.md, "The ES profile"). Entry points are
// process-wide (gl_context.h), so the profile is too; loadGl() sets it.
//
// On the ES profile the back-end keeps its desktop code: the direct-state-access entry points it
// calls on that profile's paths are emulated by binding (es_dsa_emulation.cpp), and everything
// else is refused by name before it reaches GL (esUnsupported()).

#include "si/core/status.h"
#include "si/gl/gl_context.h"
#include "si/gl/renderer.h"

namespace si::detail {

/// True while the loaded entry points are an OpenGL ES context's.
bool esProfile();
void setEsProfile(bool es);
/// True while the loaded ES context is a browser's WebGL 2 (GlInfo::webgl), which has the
/// primitive restart of GL_PRIMITIVE_RESTART_FIXED_INDEX always on and no switch for it.
bool webglProfile();
void setWebglProfile(bool webgl);

/// Marks `buffer` (a name from glCreateBuffers, not yet given storage) as an index buffer: on
/// the ES profile its uploads bind it as GL_ELEMENT_ARRAY_BUFFER, since WebGL 2 lets an index
/// buffer be bound nowhere else. No-op on desktop GL.
void esMarkIndexBuffer(unsigned buffer);

/// Loads the ES 3.0 entry points that glad's desktop loader does not load for a context whose
/// version string reads 3.x (glTexStorage2D, glVertexAttribDivisor, ...), then points the
/// direct-state-access entry points the ES profile uses at emulations by binding, each of which
/// restores every binding it changed. kBackend naming the first entry point the context lacks.
Status loadEsEntryPoints(GlGetProcAddress get_proc, void* user_data);

/// The named refusal of a capability the ES profile lacks: kUnsupported with "`what`: the
/// OpenGL ES profile has no `capability`" (es_refusals.cpp).
Status esUnsupported(const char* what, const char* capability);

/// The RendererDesc options the ES profile refuses (compute skinning, occlusion culling,
/// motion vectors, GPU timing), each by name; ok otherwise.
Status esRefusesDesc(const RendererDesc& desc);

}  // namespace si::detail
