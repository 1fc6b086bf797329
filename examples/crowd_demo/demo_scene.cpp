// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "demo_scene.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "common/face_targets.h"
#include "si/bake/lod_chain.h"
#include "si/bake/palette_file.h"
#include "si/core/impostor_level.h"
#include "si/core/lod_error.h"
#include "si/crowd/crowd_manager.h"
#include "si/gltf/gltf_import.h"

namespace demo {

const char* drawPathName(DrawPath p) {
  switch (p) {
    case DrawPath::kInstanced: return "instanced (measured choice)";
    case DrawPath::kVertexShader: return "instanced, vertex-shader skinning";
    case DrawPath::kCompute: return "instanced, compute pre-skinning";
    case DrawPath::kRigid: return "rigid (no skinning)";
    case DrawPath::kTraditional: return "traditional";
    case DrawPath::kCpuSkinned: return "cpu-skinned";
    case DrawPath::kCount: break;
  }
  return "?";
}

std::vector<std::string> defaultMix() {
  const std::string dir = SI_DEMO_ASSETS;
  return {dir + "/Fox/glTF-Binary/Fox.glb", dir + "/CesiumMan/glTF-Binary/CesiumMan.glb"};
}

si::Status DemoScene::loadCharacter(const SceneOptions& options) {
  options_ = options;
  si::Status s;
  if (!options.mix.empty()) {
    s = cast_.load(options.mix, options.rate_hz);
    if (!s.isOk()) return s;
    mixed_ = true;
  }
  if (options.model.empty()) {
    si::DefaultCharacterDesc embedded;
    embedded.moving_clips = options.root_motion;  // Else added when key R first asks.
    s = si::makeDefaultCharacter(embedded, &character_);
    // On what the head joint carries (the spear's tip left out), before the staff is attached.
    if (s.isOk() && options.faces > 0)
      si::examples::addFaceTargets(&character_, options.faces,
                                   si::examples::findHeadJoint(character_.skeleton), true);
    if (s.isOk() && options.palette.empty()) s = attachStaff();  // Before the LODs and the bake.
  } else {
    si::GltfImportReport gr;
    s = si::importGltfFile(options.model, {}, &character_, &gr);
    for (const std::string& w : gr.warnings) std::printf("warning: %s\n", w.c_str());
    if (s.isOk() && character_.clips.empty())
      s = si::Status(si::StatusCode::kUnsupported, "the model has no animation clips");
    if (s.isOk() && options.faces > 0)
      si::examples::addFaceTargets(&character_, options.faces,
                                   si::examples::findHeadJoint(character_.skeleton), true);
  }
  if (s.isOk() && options.lod_pixels > 0.0f) {  // Chains deep enough for a few pixels.
    s = si::buildLodChain(&character_.mesh, {}, nullptr);
    if (s.isOk()) s = si::measureAnimatedLodErrors(&character_, {}, nullptr);
    if (s.isOk() && options.impostors) s = si::appendImpostorLevel(&character_.mesh);
  }
  if (!s.isOk()) return s;
  // Lay the crowd out in units of the character's size (the embedded one is 2.05 units tall).
  unit_ = std::max(1e-3, double(character_.height())) / 2.05;
  if (!options.palette.empty()) {
    s = si::loadPaletteFile(options.palette, &palette_);
    if (!s.isOk()) return s;
    if (palette_.skeleton_to_palette.size() != character_.skeleton.jointCount())
      return {si::StatusCode::kInvalidArgument,
              "the palette '" + options.palette + "' was baked for a skeleton of " +
                  std::to_string(palette_.skeleton_to_palette.size()) +
                  " joints, the character has " +
                  std::to_string(character_.skeleton.jointCount())};
    options_.format = palette_.format;
    report_valid_ = false;
    printSummary();
    return s;
  }
  return bake();
}

si::Status DemoScene::bake() {
  si::BakeDesc bake;
  bake.format = options_.format;
  bake.clip_names = options_.clips;
  if (options_.rate_hz > 0.0f) {
    bake.rate_mode = si::RateMode::kFixed;
    bake.sample_rate_hz = options_.rate_hz;
  }
  const auto start = std::chrono::steady_clock::now();
  si::BakedPalette palette;
  si::Status s = si::bakePalette(character_, bake, &palette, &report_);
  if (!s.isOk()) return s;
  bake_ms_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  palette_ = std::move(palette);
  report_valid_ = true;
  printSummary();
  return s;
}

void DemoScene::printSummary() const {
  const si::Character& c = character_;
  const si::BakedPalette& p = palette_;
  std::printf("Character '%s': %zu joints, %zu vertices, height %.3f units\n", c.name.c_str(),
              c.skeleton.jointCount(), c.mesh.vertexCount(), double(c.height()));
  std::printf("%-10s", "sub-mesh");
  for (size_t l = 0; l < c.mesh.maxLodCount(); ++l) std::printf("   LOD%zu tris", l);
  std::printf("\n");
  for (size_t sm = 0; sm < c.mesh.sub_meshes.size(); ++sm) {
    std::printf("%-10s", c.mesh.sub_meshes[sm].name.c_str());
    for (size_t l = 0; l < c.mesh.sub_meshes[sm].lods.size(); ++l)
      std::printf(" %11zu", c.mesh.triangleCount(sm, l));
    std::printf("\n");
  }
  std::vector<si::LodLevelSummary> levels;  // As instances draw them.
  if (si::summarizeLodLevels(c.mesh, &levels).isOk()) {
    std::printf("%-10s", "all drawn");
    for (const si::LodLevelSummary& l : levels)
      std::printf(" %11llu", static_cast<unsigned long long>(l.triangles));
    std::printf("\n%-10s", "error (u)");
    for (const si::LodLevelSummary& l : levels) std::printf(" %11.4g", double(l.error_units));
    if (options_.lod_pixels > 0.0f)
      std::printf("\nLOD by projected error within %g pixels\n", double(options_.lod_pixels));
    else
      std::printf("\nLOD by distance lines (the technique's)\n");
  }
  std::printf("%-14s %10s %6s %9s %8s %12s\n", "clip", "duration s", "loop", "rate Hz", "frames",
              "max error");
  for (size_t i = 0; i < p.clips.size(); ++i) {
    std::printf("%-14s %10.3f %6s %9.1f %8u ", p.clips[i].name.c_str(),
                double(p.clips[i].duration_seconds),
                p.clips[i].loop_mode == si::LoopMode::kLoop ? "yes" : "no",
                p.clips[i].sampleRateHz(), p.clips[i].frame_count);
    if (report_valid_) std::printf("%12.3g\n", report_.clips[i].max_error_units);
    else std::printf("%12s\n", "(file)");
  }
  std::printf("Palette %s: %ux%u texels, %.1f KiB, %zu of %zu joints stored", 
              si::paletteFormatName(p.format), p.layout.width, p.layout.height,
              double(p.texel_bytes.size()) / 1024.0, p.palette_joints.size(),
              c.skeleton.jointCount());
  if (report_valid_)
    std::printf("; max error %.3g units (%.2g of the height)", report_.max_error_units,
                report_.max_error_ratio);
  std::printf("\n");
}

si::Status DemoScene::initGl(const si::GlInfo& info) {
  si::RendererDesc rd;
  rd.measure_gpu_time = true;
  si::Status s = renderer_.init(info, rd);
  si::CharacterId id;  // Character 0, the embedded or loaded one; the mixed cast adds more.
  if (s.isOk()) s = renderer_.addCharacter(character_, palette_, &id);
  if (s.isOk() && options_.impostors) s = buildImpostor(info, id);
  if (s.isOk()) s = batcher_.init(renderer_.batchLimits());
  if (s.isOk() && mixed_) s = cast_.upload(renderer_);
  if (s.isOk()) s = shadows_.initGl();
  if (!s.isOk()) return s;
  std::printf("Skinning path: %s (%s)\n",
              si::skinningPathName(renderer_.skinningPath(si::CharacterId{})),
              renderer_.skinningPathReason(si::CharacterId{}).c_str());
  gl_ready_ = true;
  return buildCrowd();
}

si::Status DemoScene::buildCrowd() {
  si::CrowdDesc cd;
  cd.palette = &palette_;
  cd.sub_mesh_count = uint32_t(character_.mesh.sub_meshes.size());
  cd.lod_count = uint32_t(character_.mesh.maxLodCount());
  cd.previous_records = true;  // Motion vectors (key X) may be turned on at any frame.
  cd.live_pose_capacity = kLookers + 8;  // Key G: the lookers and the fallers.
  si::Status s;
  if (options_.lod_pixels > 0.0f) {
    cd.lod_mode = si::LodMode::kScreenError;
    cd.pixel_error_budget = options_.lod_pixels;
    s = si::lodErrorsByLevel(character_.mesh, &cd.lod_errors_units);
    if (!s.isOk()) return s;
    if (options_.impostors) {  // The impostor taking over from the levels it beats, and no
      cd.lod_errors_units = impostor_errors_units_;  // far line: the whole field.
      cd.impostor_lod = uint32_t(cd.lod_errors_units.size() - 1);
      cd.max_distance_radii = -1.0f;
    }
  }
  s = crowd_.init(cd);
  if (s.isOk() && options_.events) s = addEventMarkers();
  if (!s.isOk()) return s;
  if (lod_scale_ != 1.0f) {
    std::vector<float> lines = crowd_.desc().lod_distances_radii;
    for (float& l : lines) l *= lod_scale_;
    s = crowd_.setLodDistances(lines, crowd_.desc().max_distance_radii * lod_scale_);
    if (!s.isOk()) return s;
  }
  // A field of characters on a jittered grid, 1.6 m apart, looking every which way.
  const uint32_t side = uint32_t(std::ceil(std::sqrt(double(options_.instances))));
  std::vector<glm::dvec3> positions;
  uint64_t state = options_.seed * 0x9E3779B97F4A7C15ull + 1;
  const auto jitter = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return (double((state >> 33) & 0xFFFF) / 65535.0 - 0.5) * 0.6;
  };
  // Mixed: every (kinds)th place is the main character's, the others go to the other kinds.
  const size_t kinds = 1 + otherKinds();
  std::vector<std::vector<glm::dvec3>> others(kinds - 1);
  for (uint32_t i = 0; i < options_.instances; ++i) {
    const glm::dvec3 p =
        glm::dvec3((i % side) * 1.6 + jitter(), 0.0, (i / side) * 1.6 + jitter()) * unit_;
    if (i % kinds == 0) positions.push_back(p);
    else others[i % kinds - 1].push_back(p);
  }
  if (kinds > 1) {
    s = cast_.layout(others, 1.4 * unit_, options_.seed);
    if (!s.isOk()) return s;
  }
  si::RandomCrowdDesc rc;
  rc.positions = positions;
  rc.seed = options_.seed;
  // Root motion on: the clips that carry it, applied; off: the others (all, when every clip or
  // none carries it).
  std::vector<uint32_t> travelling, in_place;
  for (uint32_t c = 0; c < palette_.clips.size(); ++c)
    (palette_.clips[c].root_motion.empty() ? in_place : travelling).push_back(c);
  if (options_.root_motion && travelling.empty())
    return {si::StatusCode::kUnsupported,
            "no clip of the palette carries root motion (si-bake --root-motion)"};
  if (options_.root_motion) rc.clips = travelling;
  else if (!travelling.empty() && !in_place.empty()) rc.clips = in_place;
  rc.root_motion = options_.root_motion;
  // The embedded character: the body always, helmet, shield and spear at random. A model:
  // every sub-mesh.
  const uint32_t all = cd.sub_mesh_count >= 32 ? 0xFFFFFFFFu : (1u << cd.sub_mesh_count) - 1u;
  rc.required_mask = options_.model.empty() ? 1u : all;
  rc.optional_mask = options_.model.empty() ? 0xEu : 0u;
  handles_.clear();
  looking_.clear();  // The new crowd holds no live poses.
  falling_.clear();
  falls_.clear();
  s = crowd_.addRandom(rc, &handles_);
  if (!s.isOk()) return s;
  starts_ = positions;
  colors_.clear();
  for (si::InstanceHandle h : handles_) {
    si::InstanceDesc d;
    s = crowd_.get(h, &d);
    if (!s.isOk()) return s;
    colors_.push_back(d.color);
  }
  s = applyProps();
  if (s.isOk() && options_.blend) s = applyBlend(0.0);
  if (s.isOk() && options_.live) s = applyLive();
  if (!s.isOk()) return s;
  return options_.layers ? applyLayers(0.0) : s;
}

double DemoScene::fieldHalfExtent() const {
  return std::ceil(std::sqrt(double(options_.instances))) * 1.6 * 0.5 * unit_;
}

glm::dvec3 DemoScene::fieldCenter() const {
  return glm::dvec3(fieldHalfExtent(), 0.0, fieldHalfExtent());
}

si::Camera DemoScene::closeUpCamera(float aspect) const {
  const double extent = 2.0 * fieldHalfExtent() / unit_;
  // Among the rows (1.6 units apart, each character turned at random), looking back at the
  // first three.
  return si::Camera::lookAt(glm::dvec3(extent * 0.5, 2.2, 5.4) * unit_,
                            glm::dvec3(extent * 0.5, 1.5, 0.0) * unit_, glm::vec3(0, 1, 0), 0.9f,
                            aspect, float(0.05 * unit_), float(2000.0 * unit_));
}

si::Camera DemoScene::overviewCamera(float aspect) const {
  // At the field's edge, 9 m up, looking in: the far line (100 character radii) bounds what a
  // large crowd shows, as the technique's LOD scheme intends.
  const double extent = 2.0 * fieldHalfExtent() / unit_;
  return si::Camera::lookAt(glm::dvec3(extent * 0.5, 9.0, -7.0) * unit_,
                            glm::dvec3(extent * 0.5, 0.0, std::min(extent * 0.45, 45.0)) * unit_,
                            glm::vec3(0, 1, 0), 0.9f, aspect, float(0.2 * unit_),
                            float(2000.0 * unit_));
}

si::Status DemoScene::measureMotion(const si::Camera& camera) {
  motion_summary_ = si::MotionSummary();
  const bool instanced = path_ == DrawPath::kInstanced || path_ == DrawPath::kVertexShader ||
                         path_ == DrawPath::kCompute;
  if (!options_.motion_vectors || !instanced || viewport_width_ == 0 || viewport_height_ == 0)
    return si::Status::ok();
  si::Status s = si::Status::ok();
  if (motion_target_.width() != viewport_width_ || motion_target_.height() != viewport_height_)
    s = motion_target_.create(viewport_width_, viewport_height_);
  if (!s.isOk()) return s;
  const si::DrawMode mode = path_ == DrawPath::kVertexShader ? si::DrawMode::kSkinned
                            : path_ == DrawPath::kCompute    ? si::DrawMode::kComputeSkinned
                                                             : si::DrawMode::kDefault;
  motion_target_.clear(glm::vec4(0.0f));
  renderer_.setMotionVectors(true);  // For this draw only: the baselines draw none.
  si::DrawStats motion_stats;
  s = renderer_.drawCrowd(si::CharacterId{}, crowd_.view(), batcher_, camera, &motion_stats, mode);
  renderer_.setMotionVectors(false);
  motion_target_.restore();
  return s.isOk() ? motion_target_.summarize(&motion_summary_) : s;
}

si::Status DemoScene::frame(double dt, const si::Camera& camera, si::DrawStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  si::Status s = moveBlends();
  if (s.isOk() && options_.live &&
      (path_ == DrawPath::kTraditional || path_ == DrawPath::kCpuSkinned)) {
    std::printf("live poses off: the %s baseline does not draw them\n", drawPathName(path_));
    s = toggleLive();
  }
  last_events_ = 0;
  const auto count_events = [&] {
    for (const si::AnimationEvent& e : crowd_.events()) last_events_ += e.count;
  };
  if (s.isOk() && options_.live) {  // Advance, write the live poses, select.
    s = crowd_.advance(dt);
    if (s.isOk()) count_events();
    if (s.isOk()) s = poseLive(camera);
    if (s.isOk()) s = crowd_.update(0.0, camera);
  } else if (s.isOk()) {
    s = crowd_.update(dt, camera);
    if (s.isOk()) count_events();
  }
  if (s.isOk() && mixed_) s = cast_.update(dt, camera);
  events_since_on_ += last_events_;
  update_ms_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (!s.isOk()) return s;
  // Shadows: the cascades select after the crowd's update, at the same clock, and draw into
  // the shadow map; the ground reads it.
  const double ground_radius = 1.6 * fieldHalfExtent();
  if (options_.shadows && !shadows_.attached()) s = shadows_.attach(crowd_);
  if (s.isOk() && options_.shadows)
    s = shadows_.render(renderer_, batcher_, camera, fieldCenter(), ground_radius);
  if (!s.isOk()) return s;
  renderer_.clear(glm::vec4(0.62f, 0.66f, 0.58f, 1.0f));
  if (options_.shadows)
    s = shadows_.drawGround(camera, fieldCenter(), ground_radius, CascadedShadows::sunDirection());
  if (!s.isOk()) return s;
  switch (path_) {
    case DrawPath::kInstanced:
      s = renderer_.drawCrowd(si::CharacterId{}, crowd_.view(), batcher_, camera, stats);
      break;
    case DrawPath::kVertexShader:
      s = renderer_.drawCrowd(si::CharacterId{}, crowd_.view(), batcher_, camera, stats,
                              si::DrawMode::kSkinned);
      break;
    case DrawPath::kCompute:
      s = renderer_.drawCrowd(si::CharacterId{}, crowd_.view(), batcher_, camera, stats,
                              si::DrawMode::kComputeSkinned);
      break;
    case DrawPath::kRigid:
      s = renderer_.drawCrowd(si::CharacterId{}, crowd_.view(), batcher_, camera, stats,
                              si::DrawMode::kRigid);
      break;
    case DrawPath::kTraditional:
      s = renderer_.drawTraditional(si::CharacterId{}, crowd_.view(), camera, stats);
      break;
    case DrawPath::kCpuSkinned:
      s = renderer_.drawCpuSkinned(si::CharacterId{}, crowd_.view(), camera, stats);
      break;
    case DrawPath::kCount: break;
  }
  if (s.isOk() && mixed_) {
    const si::DrawMode mode = path_ == DrawPath::kVertexShader ? si::DrawMode::kSkinned
                              : path_ == DrawPath::kCompute    ? si::DrawMode::kComputeSkinned
                              : path_ == DrawPath::kRigid      ? si::DrawMode::kRigid
                                                               : si::DrawMode::kDefault;
    s = cast_.draw(renderer_, batcher_, camera, mode, path_ == DrawPath::kTraditional,
                   path_ == DrawPath::kCpuSkinned, stats);
  }
  if (s.isOk()) s = measureMotion(camera);
  if (!s.isOk()) return s;
  // LOD tint (for the next frame): red LOD 0, green LOD 1, blue LOD 2, ...
  static const glm::u8vec4 kLodColors[] = {{255, 60, 60, 255},  {60, 220, 60, 255},
                                           {70, 110, 255, 255}, {240, 220, 50, 255},
                                           {220, 80, 220, 255}, {60, 220, 220, 255},
                                           {255, 160, 40, 255}, {160, 160, 160, 255}};
  if (lod_tint_ || restore_colors_) {
    for (size_t i = 0; i < handles_.size(); ++i) {
      uint32_t lod = 0;
      if (lod_tint_ && !crowd_.view().lodOf(handles_[i], &lod).isOk()) continue;
      s = crowd_.setColor(handles_[i], lod_tint_ ? kLodColors[lod % 8] : colors_[i]);
      if (!s.isOk()) return s;
    }
    restore_colors_ = false;
  }
  return s;
}

si::Status DemoScene::setInstanceCount(uint32_t count) {
  if (count == 0 || count > (1u << 20))
    return {si::StatusCode::kOutOfRange, "the crowd size must be 1 to 2^20"};
  options_.instances = count;
  return buildCrowd();
}

si::Status DemoScene::cycleFormat() {
  if (!options_.palette.empty())
    return {si::StatusCode::kUnsupported, "the palette was loaded from a file; bake to change it"};
  const si::PaletteFormat order[] = {si::PaletteFormat::kMatrix3x4F32,
                                     si::PaletteFormat::kMatrix3x4F16,
                                     si::PaletteFormat::kQuatTranslationF32};
  size_t next = 0;
  for (size_t i = 0; i < 3; ++i)
    if (order[i] == palette_.format) next = (i + 1) % 3;
  const si::PaletteFormat previous = options_.format;
  options_.format = order[next];
  si::Status s = bake();
  if (!s.isOk()) {  // E.g. the rotation format on a character with scaled joints.
    options_.format = previous;
    return s;
  }
  s = renderer_.replaceCharacter(si::CharacterId{}, character_, palette_);
  if (s.isOk()) s = buildCrowd();
  return s;
}

si::Status DemoScene::toggleMixed() {
  if (!mixed_ && cast_.size() == 0) {
    si::Status s = cast_.load(defaultMix(), options_.rate_hz);
    if (!s.isOk())
      return {s.code(), "no other kinds to mix in (crowd_demo --mix FILE,...): " + s.message()};
  }
  mixed_ = !mixed_;
  si::Status s = mixed_ && gl_ready_ ? cast_.upload(renderer_) : si::Status::ok();
  if (!s.isOk()) {
    mixed_ = false;
    return s;
  }
  return gl_ready_ ? buildCrowd() : si::Status::ok();
}

si::Status DemoScene::addEventMarkers() {
  for (uint32_t c = 0; c < palette_.clips.size(); ++c) {
    const si::BakedClip& clip = palette_.clips[c];
    si::Status s = crowd_.addClipMarker(c, 0.0, clip.name + " start");
    if (s.isOk()) s = crowd_.addClipMarker(c, 0.5 * clip.duration_seconds, clip.name + " middle");
    if (!s.isOk()) return s;
  }
  return si::Status::ok();
}

si::Status DemoScene::toggleEvents() {
  options_.events = !options_.events;
  events_since_on_ = 0;
  // Markers cannot be removed one by one: a fresh crowd (the same seeded layout) has them or not.
  return gl_ready_ ? buildCrowd() : si::Status::ok();
}

si::Status DemoScene::scaleLodLines(float factor) {
  const float scale = lod_scale_ * factor;
  std::vector<float> lines = crowd_.desc().lod_distances_radii;
  for (float& l : lines) l *= factor;
  const float far_line = crowd_.desc().max_distance_radii;
  si::Status s = crowd_.setLodDistances(lines, far_line > 0.0f ? far_line * factor : far_line);
  if (s.isOk()) lod_scale_ = scale;
  return s;
}

si::Status DemoScene::crossfadeAll() {
  const uint32_t clips = uint32_t(palette_.clips.size());
  for (si::InstanceHandle h : handles_) {
    si::InstanceDesc d;
    si::Status s = crowd_.get(h, &d);
    if (s.isOk()) s = crowd_.crossfade(h, (d.clip + 1) % clips, 0.5);
    if (!s.isOk()) return s;
  }
  return si::Status::ok();
}

}  // namespace demo
