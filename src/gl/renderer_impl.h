// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// Renderer's private state: the programs, the shared record ring and scratch buffers, the
// characters (character_slot.h) and the paths without per-character state. renderer.cpp
// dispatches to the paths; each path lives in src/gl/paths/.

#include <glad/gl.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "core/str_cat.h"
#include "gl/character_slot.h"
#include "gl/host_errors.h"
#include "gl/paths/traditional_path.h"
#include "gl/paths/vertex_shader_path.h"
#include "gl/profile/gl_profile.h"
#include "gl/programs/program_set.h"
#include "gl/resources/drawn_regions.h"
#include "gl/resources/gpu_timer.h"
#include "gl/resources/pass_timer.h"
#include "gl/resources/record_ring.h"
#include "gl/resources/scratch_buffers.h"
#include "gl/state/debug_chain.h"
#include "gl/state/gl_state_guard.h"
#include "si/crowd/crowd_export.h"
#include "si/gl/renderer.h"

namespace si {

struct Renderer::Impl {
  GlInfo info;
  RendererDesc desc;
  bool debug = false;
  uint32_t block_size = 0, capacity = 0, alignment = 256;
  uint32_t ring_frames = 0;  // RendererDesc::ring_frames (0: ringFrames() picks).
  detail::ProgramSet programs;
  detail::RecordRing ring;
  detail::DrawnRegions drawn;  // drawCrowd's recent records, read as previous ones.
  detail::ScratchBuffers scratch;
  detail::GpuTimer timer;
  detail::PassTimer pass_timer;  // RendererDesc::measure_gpu_passes.
  detail::VertexShaderPath vertex_path;
  detail::TraditionalPath traditional_path;
  std::vector<std::unique_ptr<detail::CharacterSlot>> characters;  // CharacterId::index order.
  std::vector<DrawBatch> batches;  // The batcher's draws of the current frame.
  GLuint custom_texture = detail::kNoObject;  // Renderer::setCustomTextureArray.
  uint32_t custom_layers = 0;
  // Renderer::setGpuMotionProjection.
  bool has_motion_projection = false;
  glm::mat4 motion_projection{1.0f};
  detail::DebugChain debug_chain;  // RendererDesc::debug_messages.
  // drawCrowd's program in place of the mode's while not kCount (buildImpostor's capture).
  detail::ProgramId program_override = detail::ProgramId::kCount;

  /// Uploads `palette` and `character` into `c`, prepares the paths' per-character state and
  /// picks its skinning path (measured with `light` under SkinningPath::kAutomatic). Errors are
  /// prefixed with `what` (the public call).
  Status uploadCharacter(const char* what, const Character& character,
                         const BakedPalette& palette, detail::CharacterSlot& c,
                         const glm::vec3& light);

  Status check(const char* what) const { return debug ? checkGlErrors(what) : Status::ok(); }

  /// The start of a public call named `what` that changes context state: with debug checks, or
  /// when the call always checks its errors (`reads_errors`), errors the host left pending are
  /// taken for it (gl/host_errors.h; so the call's final check reports only the library's);
  /// then the guard of `footprint` (gl/state/gl_state_guard.h)
  /// saves the state it may change (RendererDesc::restore_state) and sets the draw state.
  using Guard = std::unique_ptr<detail::GlStateGuard>;
  /// A draw's guard also takes its `camera`: a projection that mirrors the image (a y-flipped
  /// render target's, Camera::flipsWinding) draws with clockwise front faces for the call.
  Guard enter(const char* what, const detail::GlFootprint& footprint,
              const Camera* camera = nullptr, bool reads_errors = false) const {
    if (debug || reads_errors) detail::takeHostErrors(what);
    Guard guard = std::make_unique<detail::GlStateGuard>(footprint, desc.restore_state,
                                                         desc.webgl_restore_raster_state);
    if (camera != nullptr && camera->flipsWinding()) glFrontFace(GL_CW);
    return guard;
  }

  /// On the ES profile (GlInfo::es), kUnsupported naming `what` and the `capability` it lacks
  /// (gl/profile/gl_profile.h); ok on desktop GL.
  Status esRefuses(const char* what, const char* capability) const {
    return info.es ? detail::esUnsupported(what, capability) : Status::ok();
  }

  /// A crowd with an impostor level (CrowdDesc::impostor_lod) needs the character's atlas, and
  /// draws no motion vectors (`motion`: the draw would write them).
  Status impostorsDrawable(const detail::CharacterSlot& c, const CrowdManager& crowd,
                           const char* what, bool motion) const {
    if (crowd.desc().impostor_lod == 0) return Status::ok();
    if (info.es) return detail::esUnsupported(what, "impostor programs (CrowdDesc::impostor_lod)");
    if (!c.impostor.ready())
      return {StatusCode::kInvalidArgument,
              detail::strCat(what, ": the crowd draws impostors from LOD ",
                             crowd.desc().impostor_lod,
                             " (CrowdDesc::impostor_lod) but the character has no impostor atlas "
                             "(Renderer::buildImpostor)")};
    if (motion)
      return {StatusCode::kUnsupported,
              detail::strCat(what, ": impostors draw no motion vectors; turn them off "
                                   "(setMotionVectors) or draw this crowd without impostors")};
    return Status::ok();
  }
  /// The camera's depth convention (si::DepthConvention) against the context's clip control:
  /// kInvalidArgument naming `what` and both when a zero-to-one convention meets the default
  /// depth mode or the default convention meets GL_ZERO_TO_ONE (the draws would clip depth
  /// where the projection does not mean it). The ES profile has no clip control: there the
  /// default convention only.
  Status depthMatches(const Camera& camera, const char* what) const {
    GLint mode = GL_NEGATIVE_ONE_TO_ONE;
    if (!info.es) glGetIntegerv(GL_CLIP_DEPTH_MODE, &mode);
    const bool zero_to_one = camera.depth != DepthConvention::kNegativeOneToOne;
    if ((mode == GL_ZERO_TO_ONE) == zero_to_one) return Status::ok();
    return {StatusCode::kInvalidArgument,
            detail::strCat(what, ": the camera's depth convention is ",
                           depthConventionName(camera.depth),
                           " but the context's clip control depth mode is ",
                           mode == GL_ZERO_TO_ONE ? "GL_ZERO_TO_ONE" : "GL_NEGATIVE_ONE_TO_ONE",
                           " (set glClipControl to match Camera::depth)")};
  }
  /// The baselines draw meshes only: kUnsupported for a crowd with an impostor level.
  static Status noImpostors(const CrowdManager& crowd, const char* what) {
    if (crowd.desc().impostor_lod == 0) return Status::ok();
    return {StatusCode::kUnsupported,
            detail::strCat(what, ": the baseline draws meshes only; this crowd draws impostors "
                                 "(CrowdDesc::impostor_lod)")};
  }
  /// kUnsupported naming `what` while motion vectors are on: only drawCrowd and
  /// drawCrowdGpuCulled draw them.
  Status noMotion(const char* what) const {
    if (!desc.motion_vectors) return Status::ok();
    return {StatusCode::kUnsupported,
            detail::strCat(what, " draws no motion vectors; with RendererDesc::motion_vectors "
                                 "(setMotionVectors) on, draw the crowd with drawCrowd or "
                                 "drawCrowdGpuCulled")};
  }

  /// The uploaded character `id`; kInvalidArgument naming `what` when there is none, it is
  /// not complete (palette and mesh), or `crowd` (when given) plays another palette.
  Status find(CharacterId id, const char* what, detail::CharacterSlot** out,
              const CrowdManager* crowd = nullptr) {
    if (id.index >= characters.size() || !characters[id.index]->ready())
      return {StatusCode::kInvalidArgument,
              id.index == 0 && characters.size() <= 1
                  ? detail::strCat(what, ": init and addCharacter first")
                  : detail::strCat(what, ": no character ", id.index, " (", characters.size(),
                                   " added; addCharacter gives the ids)")};
    if (crowd != nullptr && crowd->desc().palette != characters[id.index]->palette.palette())
      return {StatusCode::kInvalidArgument,
              detail::strCat(what, ": the crowd plays another palette than the character's ",
                             "(draw each crowd with the CharacterId of the character uploaded ",
                             "with its palette)")};
    *out = characters[id.index].get();
    return Status::ok();
  }
  /// Whether `crowd` has room for live poses (CrowdDesc::live_pose_capacity): their frames are
  /// then uploaded after the palette's (the unpack state in the draw's footprint).
  static bool holdsLivePoses(const CrowdManager& crowd) {
    return !CrowdExport(crowd).livePoseTexels().empty();
  }
  /// Places `crowd`'s live poses after character `c`'s palette when they changed (or another
  /// crowd's are there); nothing without room for them.
  Status uploadLivePoses(detail::CharacterSlot& c, const CrowdManager& crowd, const char* what) {
    const Status s = c.palette.uploadLive(CrowdExport(crowd), crowd.identity(), info);
    return s.isOk() ? s : Status(s.code(), detail::strCat(what, ": ", s.message()));
  }
  /// The same for a view: kInvalidArgument when it is not attached to a crowd.
  Status find(CharacterId id, const char* what, detail::CharacterSlot** out, const CrowdView& view) {
    if (view.crowd() == nullptr)
      return {StatusCode::kInvalidArgument,
              detail::strCat(what, ": the view is not attached to a crowd (init() the crowd, and "
                                   "the view with CrowdView::init)")};
    return find(id, what, out, view.crowd());
  }

  /// Ring regions per character: RendererDesc::ring_frames, else 3, and 4 with motion vectors
  /// (a region the next draw reads as its previous records is held one draw longer).
  uint32_t ringFrames() const {
    return ring_frames != 0 ? ring_frames : desc.motion_vectors ? 4u : 3u;
  }
  /// The record ring keeps ringFrames() regions per character: each character's draw takes
  /// one, so a frame drawing every character waits for none of this frame's regions. Nothing
  /// to do when the count is unchanged; otherwise it waits for the GPU and drops the buffer.
  void sizeRing() {
    ring.setRegions(ringFrames() * uint32_t(std::max<size_t>(1, characters.size())));
  }

  detail::DrawResources resources(detail::CharacterSlot& c) {
    detail::DrawResources r;
    r.info = &info;
    r.desc = &desc;
    r.programs = detail::ProgramTable{&programs, c.material, c.character.alpha_masked,
                                      c.character.meshFeatures()};
    r.palette = &c.palette;
    r.character = &c.character;
    r.preskin = &c.preskin;
    r.ring = &ring;
    r.scratch = &scratch;
    r.block_size = block_size;
    r.capacity = capacity;
    r.alignment = alignment;
    r.custom_texture = custom_texture;
    r.custom_layers = custom_layers;
    r.impostor = &c.impostor;
    r.passes = desc.measure_gpu_passes ? &pass_timer : nullptr;
    return r;
  }

  /// The crowd-only baselines (no batcher, no mode): drawTraditional, or with `cpu`
  /// drawCpuSkinned, of character `id` for `view` seen by `camera`, refused where they cannot
  /// draw (the ES profile, motion vectors, impostors); runPath(), the error check and the stats
  /// (when non-null).
  Status drawBaseline(CharacterId id, bool cpu, const CrowdView& view, const Camera& camera,
                      const glm::vec3& light, DrawStats* stats) {
    const char* what = cpu ? "drawCpuSkinned" : "drawTraditional";
    detail::CharacterSlot* c = nullptr;
    Status s = find(id, what, &c, view);
    if (s.isOk()) s = depthMatches(camera, what);
    if (s.isOk())
      s = esRefuses(
          what, cpu ? "storage buffers (a baseline)" : "traditional program (a desktop baseline)");
    if (s.isOk()) s = noMotion(what);
    if (s.isOk()) s = noImpostors(*view.crowd(), what);
    if (!s.isOk()) return s;
    detail::DrawPath& p = cpu ? static_cast<detail::DrawPath&>(c->cpu_path) : traditional_path;
    const auto t0 = std::chrono::steady_clock::now();
    Guard guard = enter(what, detail::drawFootprint(), &camera);
    const detail::PathFrame frame = detail::viewFrame(view, camera, light);
    DrawStats st;
    s = runPath(*c, p, frame, t0, stats != nullptr, &st, guard);
    if (s.isOk()) s = check(what);
    if (stats != nullptr) *stats = st;
    return s;
  }

  /// Runs `p` for character `c` and `frame`: its uploads, then its commands under the GPU timer
  /// (when asked for and `stats` is non-null), inside the caller's state guard (enter()), which
  /// it then ends (the host's state restored). Fills `st` with what it drew, the CPU
  /// milliseconds since `t0` (the state's save and restore included) and the GPU milliseconds.
  Status runPath(detail::CharacterSlot& c, detail::DrawPath& p, const detail::PathFrame& frame,
                 std::chrono::steady_clock::time_point t0, bool timed, DrawStats* st,
                 Guard& guard) {
    detail::DrawResources r = resources(c);
    // Pass times (the uploads' included) for draws that return stats, ended whatever happens.
    if (r.passes != nullptr && timed)
      st->gpu_pass_ticket = pass_timer.begin(kGpuPassTickets);
    else
      r.passes = nullptr;
    Status s = p.uploadFrame(r, frame);
    detail::markPass(r, GpuPass::kUpload);
    if (!s.isOk()) {
      pass_timer.end(GpuPass::kUpload);
      return s;
    }
    timer.begin(desc.measure_gpu_time && timed);
    // A double-sided material's back faces are drawn (the surface turns their normal).
    if (c.character.double_sided) glDisable(GL_CULL_FACE);
    s = p.draw(r, frame, st);
    if (c.character.double_sided) glEnable(GL_CULL_FACE);
    pass_timer.end(GpuPass::kDraw);
    timer.stop();
    guard.reset();
    st->cpu_submit_ms = detail::msSince(t0);  // Before the (blocking) timer read.
    st->gpu_ms = timer.read();
    // ES 3.0 has no reset status (ES 3.2 and KHR_robustness do).
    const GLenum reset = glGetGraphicsResetStatus ? glGetGraphicsResetStatus() : GL_NO_ERROR;
    if (reset != GL_NO_ERROR)
      return {StatusCode::kBackend,
              reset == GL_GUILTY_CONTEXT_RESET     ? "the GL context was lost (reset, caused here)"
              : reset == GL_INNOCENT_CONTEXT_RESET ? "the GL context was lost (reset elsewhere)"
                                                   : "the GL context was lost (reset)"};
    return s;
  }
};

}  // namespace si
