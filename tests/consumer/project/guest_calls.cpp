// See guest_calls.h.
#include "guest_calls.h"

#include <glm/gtc/matrix_transform.hpp>

#include <glad/gl.h>

#include <functional>
#include <memory>
#include <vector>

#include "host_state.h"
#include "si/bake/animation_baker.h"
#include "si/core/default_character.h"
#include "si/core/impostor_level.h"
#include "si/core/layer_mask.h"
#include "si/crowd/crowd_manager.h"
#include "si/crowd/instance_batcher.h"
#include "si/gl/gl_context.h"
#include "si/gl/motion_target.h"
#include "si/gl/renderer.h"

namespace host {

namespace {

constexpr GLuint kMarker = 0x5157;  // The id of the engine's own debug messages.

// The engine's KHR_debug callback: counts its own markers.
struct DebugLog {
  int markers = 0;
};
void GLAD_API_PTR engineCallback(GLenum source, GLenum, GLuint id, GLenum, GLsizei, const GLchar*,
                                 const void* user) {
  if (source == GL_DEBUG_SOURCE_APPLICATION && id == kMarker)
    ++static_cast<DebugLog*>(const_cast<void*>(user))->markers;
}

// `c` with a morph target that swells its head (the vertices above 85 % of its height), its
// weight going 0, 1, 0 over each clip.
void addHeadTarget(si::Character* c) {
  si::MorphTarget t;
  t.name = "swell";
  const si::Aabb box = c->bindPoseBounds();
  const float floor = box.min.y + 0.85f * (box.max.y - box.min.y);
  for (uint32_t v = 0; v < uint32_t(c->mesh.vertexCount()); ++v)
    if (c->mesh.positions[v].y > floor) {
      t.vertices.push_back(v);
      t.position_deltas.push_back(c->mesh.normals[v] * (0.03f * c->height()));
    }
  c->mesh.morph_targets.push_back(std::move(t));
  for (si::Clip& clip : c->clips) {
    si::MorphWeightTrack w;
    w.target_count = 1;
    w.interpolation = si::Interpolation::kLinear;
    w.times_seconds = {0.0f, 0.5f * clip.duration_seconds, clip.duration_seconds};
    w.values = {0.0f, 1.0f, 0.0f};
    clip.morph_tracks = {w};
  }
}

// A crowd of 12 of the embedded character close to the camera: clips, times, tints, armour;
// with `overlays`, every third waves its right arm over what it plays.
si::Status makeCrowd(const si::Character& c, const si::BakedPalette& palette, bool overlays,
                     si::CrowdManager* crowd, si::Camera* camera, uint32_t live_poses = 0) {
  si::CrowdDesc cd;
  cd.live_pose_capacity = live_poses;
  cd.palette = &palette;
  cd.sub_mesh_count = uint32_t(c.mesh.sub_meshes.size());
  cd.lod_count = uint32_t(c.mesh.sub_meshes[0].lods.size());
  cd.previous_records = true;
  si::Status s = crowd->init(cd);
  uint32_t mask = 0;
  if (s.isOk() && overlays) {
    si::LayerMask arm;
    s = si::buildLayerMask(c.skeleton, palette, "right arm", {"r_clavicle"}, &arm);
    if (s.isOk()) s = crowd->addLayerMask(arm, &mask);
  }
  for (int k = 0; k < 12 && s.isOk(); ++k) {
    si::InstanceDesc d;
    d.position = glm::dvec3(-2.5 + 0.9 * (k % 6), 0.0, -1.0 - 1.4 * (k / 6));
    d.clip = uint32_t(k) % uint32_t(palette.clips.size());
    d.time_seconds = 0.11 * k;
    d.variation_mask = 1u | (uint32_t(k) << 1);
    d.color = glm::u8vec4(uint8_t(40 + 17 * k), uint8_t(220 - 13 * k), 90, 255);
    d.custom_layer = uint8_t(k % 3);
    si::InstanceHandle h;
    s = crowd->add(d, &h);
    if (s.isOk() && overlays && k % 3 == 0)
      s = crowd->playOverlay(h, uint32_t(palette.findClip("wave")), mask, 1.0f, 0.0);
    if (s.isOk() && uint32_t(k) < live_poses) {  // The engine poses it: clip 0's first frame.
      std::vector<glm::mat4> pose(palette.palette_joints.size());
      for (uint32_t slot = 0; slot < pose.size(); ++slot)
        pose[slot] = si::decodeJoint(palette, 0, 0, slot);
      s = crowd->setLivePose(h, pose);
    }
  }
  *camera = si::Camera::lookAt({0.0, 1.6, 4.0}, {0.0, 0.9, -1.5}, glm::vec3(0, 1, 0), 0.9f, 1.0f,
                               0.1f, 100.0f);
  // The engine's projection matches its zero-to-one clip control (host_state.cpp); the draws
  // refuse a camera that does not.
  camera->depth = si::DepthConvention::kZeroToOne;
  camera->projection = glm::perspectiveRH_ZO(0.9f, 1.0f, 0.1f, 100.0f);
  if (s.isOk()) s = crowd->update(1.0 / 30.0, *camera);
  if (s.isOk()) s = crowd->update(1.0 / 30.0, *camera);  // Previous records of the first.
  return s;
}

// Every instance at the impostor level of `c` (whose last level is one, si::appendImpostorLevel).
si::Status makeImpostorCrowd(const si::Character& c, const si::BakedPalette& palette,
                             const si::Camera& camera, si::CrowdManager* crowd) {
  si::CrowdDesc cd;
  cd.palette = &palette;
  cd.sub_mesh_count = uint32_t(c.mesh.sub_meshes.size());
  cd.lod_count = uint32_t(c.mesh.maxLodCount());
  cd.impostor_lod = cd.lod_count - 1;
  for (uint32_t l = 1; l < cd.lod_count; ++l) cd.lod_distances_radii.push_back(1e-6f * float(l));
  si::Status s = crowd->init(cd);
  for (int k = 0; k < 12 && s.isOk(); ++k) {
    si::InstanceDesc d;
    d.position = glm::dvec3(-2.5 + 0.9 * (k % 6), 0.0, -1.0 - 1.4 * (k / 6));
    d.clip = uint32_t(k) % uint32_t(palette.clips.size());
    d.color = glm::u8vec4(uint8_t(40 + 17 * k), uint8_t(220 - 13 * k), 90, 255);
    si::InstanceHandle h;
    s = crowd->add(d, &h);
  }
  if (s.isOk()) s = crowd->update(1.0 / 30.0, camera);
  return s;
}

class Checker {
 public:
  Checker(const HostState& state, DebugLog& log, GuestReport& report)
      : state_(state), log_(log), report_(report) {}

  // Runs `call` in the engine's state; afterwards every piece of it must be unchanged (except
  // those named from `ignore_prefix` on) and the engine's callback must receive its own message.
  // With `host_query`, the engine has its own GL_TIME_ELAPSED query running around the call.
  void check(const std::string& what, const std::function<si::Status()>& call,
             const std::string& ignore_prefix = "", bool host_query = false) {
    state_.apply();
    if (host_query) glBeginQuery(GL_TIME_ELAPSED, query());
    const GlSnapshot before = snapshot(&report_.failures);
    report_.values = before.values.size();
    const si::Status s = call();
    if (!s.isOk()) report_.failures.push_back(what + ": " + s.toString());
    const GlSnapshot after = snapshot(&report_.failures);
    if (host_query) glEndQuery(GL_TIME_ELAPSED);
    const std::string changed = differences(before, after, ignore_prefix);
    if (!changed.empty()) report_.failures.push_back(what + " changed " + changed);
    const int markers = log_.markers;
    glDebugMessageInsert(GL_DEBUG_SOURCE_APPLICATION, GL_DEBUG_TYPE_MARKER, kMarker,
                         GL_DEBUG_SEVERITY_NOTIFICATION, -1, "the engine's marker");
    if (log_.markers != markers + 1)
      report_.failures.push_back(what + ": the engine's debug callback did not get its message");
    ++report_.calls;
  }

  ~Checker() {
    if (query_ != 0) glDeleteQueries(1, &query_);
  }

 private:
  GLuint query() {
    if (query_ == 0) glGenQueries(1, &query_);
    return query_;
  }

  const HostState& state_;
  DebugLog& log_;
  GuestReport& report_;
  GLuint query_ = 0;
};

}  // namespace

GuestReport checkEveryCall(void* (*get_proc)(void* user, const char* name), void* user,
                           unsigned width, unsigned height) {
  GuestReport report;
  const auto fail = [&](const std::string& what, const si::Status& s) {
    report.failures.push_back(what + ": " + s.toString());
    return report;
  };
  si::GlInfo info;
  si::Status s = si::loadGl(get_proc, user, &info);
  if (!s.isOk()) return fail("loadGl", s);
  si::Character character;
  s = si::makeDefaultCharacter({}, &character);
  si::BakeDesc bd;
  bd.rate_mode = si::RateMode::kFixed;
  bd.sample_rate_hz = 30.0f;
  si::BakedPalette palette;
  if (s.isOk()) s = si::bakePalette(character, bd, &palette, nullptr);
  si::CrowdManager plain, layered;
  si::Camera camera;
  if (s.isOk()) s = makeCrowd(character, palette, false, &plain, &camera);
  if (s.isOk()) s = makeCrowd(character, palette, true, &layered, &camera);
  if (!s.isOk()) return fail("setting up the crowds", s);

  HostState state;
  const std::string made = state.create(width, height);
  if (!made.empty()) {
    report.failures.push_back(made);
    return report;
  }
  DebugLog log;
  glDebugMessageCallback(&engineCallback, &log);
  Checker checker(state, log, report);

  auto renderer = std::make_unique<si::Renderer>();
  si::CharacterId id;
  si::InstanceBatcher batcher;
  checker.check("Renderer::init", [&] { return renderer->init(info, {}); });
  checker.check("Renderer::addCharacter (the automatic skinning path measures both paths)", [&] {
    return renderer->addCharacter(character, palette, &id);
  });
  s = batcher.init(renderer->batchLimits());
  if (!s.isOk()) return fail("InstanceBatcher::init", s);
  checker.check("Renderer::setCustomTextureArray",
                [&] { return renderer->setCustomTextureArray(state.customTextureArray()); });
  const std::pair<si::DrawMode, const char*> modes[] = {
      {si::DrawMode::kDefault, "kDefault"},     {si::DrawMode::kSkinned, "kSkinned"},
      {si::DrawMode::kComputeSkinned, "kComputeSkinned"}, {si::DrawMode::kDepthOnly, "kDepthOnly"},
      {si::DrawMode::kRigid, "kRigid"}};
  for (const si::CrowdManager* crowd : {&plain, &layered}) {
    const std::string overlays = crowd == &layered ? ", overlays" : "";
    for (const auto& [mode, name] : modes)
      checker.check(std::string("Renderer::drawCrowd(") + name + overlays + ")", [&, mode = mode] {
        return renderer->drawCrowd(id, crowd->view(), batcher, camera, nullptr, mode);
      });
    renderer->setMotionVectors(true);
    for (si::DrawMode mode : {si::DrawMode::kSkinned, si::DrawMode::kComputeSkinned})
      checker.check(
          std::string("Renderer::drawCrowd(") +
              (mode == si::DrawMode::kSkinned ? "kSkinned" : "kComputeSkinned") +
              ", motion vectors" + overlays + ")",
          [&] { return renderer->drawCrowd(id, crowd->view(), batcher, camera, nullptr, mode); });
    for (bool occlusion : {false, true}) {
      renderer->setGpuOcclusionCulling(occlusion);
      for (si::DrawMode mode : {si::DrawMode::kSkinned, si::DrawMode::kComputeSkinned})
        checker.check(
            std::string("Renderer::drawCrowdGpuCulled(") +
                (mode == si::DrawMode::kSkinned ? "kSkinned" : "kComputeSkinned") +
                (occlusion ? ", occlusion culling" : "") + ", motion vectors" + overlays + ")",
            [&] { return renderer->drawCrowdGpuCulled(id, crowd->view(), camera, nullptr, mode); });
    }
    renderer->setGpuOcclusionCulling(false);
    renderer->setMotionVectors(false);
    checker.check("Renderer::drawTraditional" + overlays,
                  [&] { return renderer->drawTraditional(id, crowd->view(), camera, nullptr); });
    checker.check("Renderer::drawCpuSkinned" + overlays,
                  [&] { return renderer->drawCpuSkinned(id, crowd->view(), camera, nullptr); });
  }
  // Impostors: a second character with an impostor level, its atlas drawn on the GPU, and a
  // crowd drawn as impostors on the instanced and GPU-driven paths, colour and depth only.
  si::Character far_character = character;
  s = si::appendImpostorLevel(&far_character.mesh);
  si::CharacterId far_id;
  if (s.isOk()) s = renderer->addCharacter(far_character, palette, &far_id);
  si::CrowdManager far_crowd;
  if (s.isOk()) s = makeImpostorCrowd(far_character, palette, camera, &far_crowd);
  if (!s.isOk()) return fail("setting up the impostor crowd", s);
  si::ImpostorDesc small;
  small.azimuths = 4;
  small.elevations_degrees = {0.0f};
  small.frames_per_clip = 2;
  checker.check("Renderer::buildImpostor", [&] { return renderer->buildImpostor(far_id, small); });
  for (const auto& [mode, name] : {modes[0], modes[3]}) {
    checker.check(std::string("Renderer::drawCrowd(") + name + ", impostors)", [&, mode = mode] {
      return renderer->drawCrowd(far_id, far_crowd.view(), batcher, camera, nullptr, mode);
    });
    checker.check(
        std::string("Renderer::drawCrowdGpuCulled(") + name + ", impostors)", [&, mode = mode] {
          return renderer->drawCrowdGpuCulled(far_id, far_crowd.view(), camera, nullptr, mode);
        });
  }
  // Morph targets: a third character whose clips swell its head; its draws bind the morph
  // texture.
  si::Character faced = character;
  addHeadTarget(&faced);
  si::BakedPalette faced_palette;
  s = si::bakePalette(faced, bd, &faced_palette, nullptr);
  si::CharacterId faced_id;
  if (s.isOk()) s = renderer->addCharacter(faced, faced_palette, &faced_id);
  si::CrowdManager faced_crowd;
  if (s.isOk()) s = makeCrowd(faced, faced_palette, false, &faced_crowd, &camera);
  if (!s.isOk()) return fail("setting up the morph targets' crowd", s);
  for (const auto& [mode, name] : {modes[1], modes[2], modes[3]}) {
    checker.check(
        std::string("Renderer::drawCrowd(") + name + ", morph targets)", [&, mode = mode] {
          return renderer->drawCrowd(faced_id, faced_crowd.view(), batcher, camera, nullptr, mode);
        });
    checker.check(
        std::string("Renderer::drawCrowdGpuCulled(") + name + ", morph targets)", [&, mode = mode] {
          return renderer->drawCrowdGpuCulled(faced_id, faced_crowd.view(), camera, nullptr, mode);
        });
  }
  checker.check("Renderer::drawTraditional, morph targets", [&] {
    return renderer->drawTraditional(faced_id, faced_crowd.view(), camera, nullptr);
  });
  // Live poses: two instances the engine poses; drawCrowd and the GPU-driven path upload their
  // frames after the palette's (the unpack state), the GPU-driven path their slots too.
  si::CrowdManager live_crowd;
  s = makeCrowd(character, palette, false, &live_crowd, &camera, 2);
  if (!s.isOk()) return fail("setting up the live poses' crowd", s);
  for (const auto& [mode, name] : {modes[1], modes[2]}) {
    checker.check(std::string("Renderer::drawCrowd(") + name + ", live poses)", [&, mode = mode] {
      return renderer->drawCrowd(id, live_crowd.view(), batcher, camera, nullptr, mode);
    });
    checker.check(
        std::string("Renderer::drawCrowdGpuCulled(") + name + ", live poses)", [&, mode = mode] {
          return renderer->drawCrowdGpuCulled(id, live_crowd.view(), camera, nullptr, mode);
        });
  }
  // A material of the engine's, reading a uniform block of its own (at binding 7, which the
  // engine's state binds) and the instance handle (its block at storage binding 29, which the
  // engine's state binds too), on meshes and impostors.
  si::MaterialDesc engine_material;
  engine_material.name = "engine";
  engine_material.source =
      "layout(location = 0) out vec4 o_color;\n"
      "layout(std140, binding = 7) uniform EngineTone { vec4 tone; };\n"
      "void siMaterial(SiSurface s) {\n"
      "  o_color = vec4(siSurfaceAlbedo(s) * tone.rgb, s.instance == 0u ? 0.5 : 1.0);\n"
      "}\n";
  engine_material.instance_handle = true;
  si::MaterialId material;
  checker.check("Renderer::addMaterial",
                [&] { return renderer->addMaterial(engine_material, &material); });
  for (const si::CharacterId kind : {id, far_id}) {
    const si::Status set = renderer->setMaterial(kind, material);
    if (!set.isOk()) return fail("Renderer::setMaterial", set);
    const si::CrowdManager& crowd = kind == id ? plain : far_crowd;
    checker.check("Renderer::drawCrowd (a host material)", [&] {
      return renderer->drawCrowd(kind, crowd.view(), batcher, camera, nullptr);
    });
    checker.check("Renderer::drawCrowdGpuCulled (a host material)", [&] {
      return renderer->drawCrowdGpuCulled(kind, crowd.view(), camera, nullptr);
    });
  }
  std::vector<glm::uvec2> selection;
  checker.check("Renderer::readGpuSelection",
                [&] { return renderer->readGpuSelection(id, &selection); });
  std::vector<glm::vec3> positions;
  for (si::SkinningPath path : {si::SkinningPath::kVertexShader, si::SkinningPath::kCompute})
    checker.check(
        std::string("Renderer::captureSkinnedPositions(") + si::skinningPathName(path) + ")", [&] {
          return renderer->captureSkinnedPositions(id, plain.view().records()[0], &positions, path);
        });
  checker.check("Renderer::clear", [&] {
    renderer->clear(glm::vec4(0.2f, 0.3f, 0.4f, 1.0f));
    return si::Status::ok();
  });
  checker.check("Renderer::shutdown", [&] {
    renderer->shutdown();
    return si::Status::ok();
  });

  // The motion target's reads.
  si::MotionTarget target;
  checker.check("MotionTarget::create", [&] { return target.create(width, height); });
  std::vector<uint8_t> color;
  std::vector<glm::vec2> motion;
  std::vector<float> depth;
  si::MotionSummary summary;
  checker.check("MotionTarget::readColor", [&] { return target.readColor(&color); });
  checker.check("MotionTarget::readMotion", [&] { return target.readMotion(&motion); });
  checker.check("MotionTarget::readDepth", [&] { return target.readDepth(&depth); });
  checker.check("MotionTarget::summarize", [&] { return target.summarize(&summary); });
  target.release();

  // Opted into the driver's messages, and timing its draws while the engine times its frame
  // with a query of its own: the renderer's callback stands in front of the engine's while it
  // lives (the engine's still gets every message), and from before init to after shutdown
  // nothing of the engine's state differs, its callback included.
  si::RendererDesc chained;
  chained.debug_messages = true;
  chained.measure_gpu_time = true;
  chained.measure_gpu_passes = true;
  chained.skinning_path = si::SkinningPath::kCompute;
  state.apply();
  const GlSnapshot start = snapshot(&report.failures);
  renderer = std::make_unique<si::Renderer>();
  checker.check(
      "Renderer::init (debug_messages, measure_gpu_time, measure_gpu_passes)",
      [&] { return renderer->init(info, chained); }, "GL_DEBUG_CALLBACK");
  checker.check("Renderer::addCharacter (debug_messages)",
                [&] { return renderer->addCharacter(character, palette, &id); },
                "GL_DEBUG_CALLBACK");
  si::DrawStats stats;
  checker.check(
      "Renderer::drawCrowd (debug_messages, measure_gpu_time, the engine's query running)",
      [&] { return renderer->drawCrowd(id, layered.view(), batcher, camera, &stats); },
      "GL_DEBUG_CALLBACK", true);
  checker.check(
      "Renderer::drawCrowdGpuCulled (measure_gpu_time, the engine's query running)",
      [&] { return renderer->drawCrowdGpuCulled(id, plain.view(), camera, &stats); },
      "GL_DEBUG_CALLBACK", true);
  // Its pass times read with the engine's query buffer bound (the results go to memory).
  checker.check(
      "Renderer::readGpuPasses (the engine's query running)",
      [&] {
        si::GpuPassTimes times;
        return renderer->readGpuPasses(stats.gpu_pass_ticket, &times);
      },
      "GL_DEBUG_CALLBACK", true);
  checker.check("Renderer::shutdown (debug_messages)", [&] {
    renderer->shutdown();
    return si::Status::ok();
  }, "GL_DEBUG_CALLBACK");
  const std::string changed = differences(start, snapshot(&report.failures));
  if (!changed.empty())
    report.failures.push_back("a debug_messages renderer from init to shutdown changed " + changed);
  renderer.reset();
  glDebugMessageCallback(nullptr, nullptr);
  state.release();
  return report;
}

}  // namespace host
