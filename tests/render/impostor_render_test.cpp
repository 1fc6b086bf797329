// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Animated impostors (Renderer::buildImpostor, CrowdDesc::impostor_lod): the GPU-driven path's
// selection and impostor draw give the instanced path's image; an impostor at the height
// where its measured image error is one pixel differs from the mesh there by about that much;
// bad input refused with named statuses.
#include <glad/gl.h>

#include <algorithm>
#include <cmath>

#include "render/impostor_fixture.h"
#include "render/two_targets.h"
#include "si/crowd/crowd_manager.h"
#include "si/gl/image_lod_error.h"

namespace si {
namespace {

using namespace test;

// Rows at 4, 30, 70 and 150 units in front of lodCamera(); lines (radius 1) put the last two
// rows past the impostor's line unless `lines` says otherwise. With `live_poses`, every third
// instance holds a live pose: the matrices of another clip's frame.
void impostorCrowd(std::vector<float> lines, uint32_t impostor_lod, CrowdManager* crowd,
                   bool live_poses = false) {
  CrowdDesc cd;
  cd.live_pose_capacity = live_poses ? 32 : 0;
  cd.palette = &palette();
  cd.sub_mesh_count = 4;
  cd.lod_count = impostorLevels();
  cd.character_radius = 1.0f;
  cd.lod_distances_radii = std::move(lines);
  cd.max_distance_radii = -1.0f;
  cd.impostor_lod = impostor_lod;
  ASSERT_TRUE(crowd->init(cd).isOk());
  const uint32_t clips = uint32_t(palette().clips.size());
  const double rows[4] = {-4.0, -30.0, -70.0, -150.0}, spacing[4] = {1.2, 4.0, 8.0, 16.0};
  for (int row = 0; row < 4; ++row)
    for (int k = 0; k < 8; ++k) {
      InstanceDesc d;
      d.position = glm::dvec3((k - 3.5) * spacing[row], 0.0, rows[row]);
      d.rotation = glm::angleAxis(0.7f * float(k + row), glm::vec3(0, 1, 0));
      d.variation_mask = k % 3 == 0 ? 0x6u : 1u | (uint32_t(k) << 1);  // Some without part 0.
      d.clip = uint32_t(k) % clips;
      d.time_seconds = 0.13 * k;
      d.scale = 1.0f + 0.1f * float(row);
      d.color = glm::u8vec4(uint8_t(40 + 30 * k), uint8_t(200 - 20 * k), uint8_t(60 + 50 * row), 255);
      InstanceHandle h;
      ASSERT_TRUE(crowd->add(d, &h).isOk());
      if (!live_poses || k % 3 != 1) continue;
      const uint32_t other = (uint32_t(k) + 1) % clips;
      std::vector<glm::mat4> pose(palette().palette_joints.size());
      for (uint32_t slot = 0; slot < pose.size(); ++slot)
        pose[slot] = decodeJoint(palette(), other, uint32_t(row), slot);
      ASSERT_TRUE(crowd->setLivePose(h, pose).isOk());
    }
  ASSERT_TRUE(crowd->advance(0.4).isOk());
  ASSERT_TRUE(crowd->update(0.0, lodCamera()).isOk());
}

// A renderer of impostorCharacter() with its small atlas; `counts`: RendererDesc::
// measure_gpu_time, so that the GPU-driven path reads back its counts into the draw's stats.
void initImpostorRenderer(const GlInfo& info, bool counts, Renderer* r, CharacterId* id) {
  RendererDesc rd;
  rd.measure_gpu_time = counts;
  ASSERT_TRUE(r->init(info, rd).isOk());
  ASSERT_TRUE(r->addCharacter(impostorCharacter(), palette(), id).isOk());
  const Status s = r->buildImpostor(*id, smallImpostor());
  ASSERT_TRUE(s.isOk()) << s.toString();
}

uint32_t backgroundlessPixels(const std::vector<uint8_t>& rgba) {
  uint32_t n = 0;
  for (size_t p = 0; p < rgba.size(); p += 4)
    n += (rgba[p] != 51 || rgba[p + 1] != 64 || rgba[p + 2] != 77) ? 1u : 0u;
  return n;
}

TEST_P(RenderTest, ImpostorsDrawTheInstancedPathsImageOnTheGpuDrivenPath) {
  CrowdManager crowd;
  impostorCrowd(linesTo(60.0f), impostorLevels() - 1, &crowd);
  ASSERT_EQ(crowd.view().stats().per_lod[impostorLevels() - 1], 16u);
  const auto renderer = [&](Renderer* r, SkinningPath path) {
    RendererDesc rd;
    rd.skinning_path = path;
    rd.measure_gpu_time = true;  // The GPU-driven path reads back its counts.
    rd.measure_gpu_passes = true;
    ASSERT_TRUE(r->init(info_, rd).isOk());
    CharacterId id;
    ASSERT_TRUE(r->addCharacter(impostorCharacter(), palette(), &id).isOk());
    ImpostorInfo info;
    const Status s = r->buildImpostor(id, smallImpostor(), &info);
    ASSERT_TRUE(s.isOk()) << s.toString();
    EXPECT_TRUE(r->hasImpostor(id));
    EXPECT_EQ(info.views, 16u);
    EXPECT_EQ(info.cells, info.views * info.frames);
    EXPECT_GE(uint64_t(info.width / 32) * (info.height / 32), info.cells);
  };
  Renderer vs, cs;
  renderer(&vs, SkinningPath::kVertexShader);
  renderer(&cs, SkinningPath::kCompute);
  DrawStats reference_stats;
  const std::vector<uint8_t> reference = draw(vs, crowd, lodCamera(), 0, false, &reference_stats);
  // The impostors drew: about as many pixels as the same crowd with meshes everywhere.
  CrowdManager meshes;
  impostorCrowd(linesTo(1e6f), 0, &meshes);
  const std::vector<uint8_t> mesh_image = draw(vs, meshes, lodCamera(), 0);
  const double covered = backgroundlessPixels(reference), mesh_covered = backgroundlessPixels(mesh_image);
  EXPECT_NEAR(covered / mesh_covered, 1.0, 0.1) << covered << " against " << mesh_covered;
  const Diff to_meshes = compare(reference, mesh_image, nullptr);
  EXPECT_GT(to_meshes.share, 0.0);   // Not the meshes' image,
  EXPECT_LT(to_meshes.share, 0.03);  // but close: small and far.

  expectEveryCaseDraws({{"compute", &cs, Path::kCompute, false, DrawMode::kComputeSkinned},
                        {"gpu-driven", &vs, Path::kInstanced, true, DrawMode::kSkinned},
                        {"gpu-driven compute", &cs, Path::kInstanced, true,
                         DrawMode::kComputeSkinned}},
                       crowd, lodCamera(), reference, reference_stats);
  // Their GPU time is a pass of its own (RendererDesc::measure_gpu_passes) on both kinds of path.
  DrawStats gpu_driven;
  ASSERT_TRUE(vs.drawCrowdGpuCulled(CharacterId{}, crowd.view(), lodCamera(), &gpu_driven).isOk());
  std::vector<uint8_t> image;
  ASSERT_TRUE(context_->readPixels(&image).isOk());
  for (const uint64_t ticket : {reference_stats.gpu_pass_ticket, gpu_driven.gpu_pass_ticket}) {
    GpuPassTimes t;
    ASSERT_TRUE(vs.readGpuPasses(ticket, &t).isOk());
    EXPECT_TRUE(t.ready);
    EXPECT_GT(t.at(GpuPass::kImpostors), 0.0);
    EXPECT_GT(t.at(GpuPass::kDraw), 0.0);
  }
}

// A shadow view's impostors: the GPU-driven path's depth-only draw (its quads computed by the
// impostor quads pass) writes the instanced path's depth, and both write depth exactly where
// the colour draw covers.
TEST_P(RenderTest, ImpostorsInADepthOnlyViewWriteTheInstancedPathsDepth) {
  CrowdManager crowd;
  impostorCrowd(linesTo(60.0f), impostorLevels() - 1, &crowd);
  ASSERT_EQ(crowd.view().stats().per_lod[impostorLevels() - 1], 16u);
  Renderer r;
  CharacterId id;
  initImpostorRenderer(info_, false, &r, &id);
  // Only the impostors: the two far rows (the near ones are meshes).
  const Camera camera = lodCamera();
  const std::vector<uint8_t> colour = draw(r, crowd, camera, 0);
  r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));  // draw()'s background.
  std::vector<uint8_t> background;
  ASSERT_TRUE(context_->readPixels(&background).isOk());
  const auto depth_of = [&](bool gpu_driven) {
    InstanceBatcher batcher;
    EXPECT_TRUE(batcher.init(r.batchLimits()).isOk());
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    DrawStats st;
    const Status s =
        gpu_driven ? r.drawCrowdGpuCulled(id, crowd.view(), camera, &st, DrawMode::kDepthOnly)
                   : r.drawCrowd(id, crowd.view(), batcher, camera, &st, DrawMode::kDepthOnly);
    EXPECT_TRUE(s.isOk()) << s.toString();
    std::vector<float> depth(size_t(kSize) * kSize, -1.0f);
    glReadPixels(0, 0, GLsizei(kSize), GLsizei(kSize), GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
    return depth;
  };
  const std::vector<float> instanced = depth_of(false), gpu_driven = depth_of(true);
  uint32_t written = 0, apart = 0, uncovered = 0;
  double worst = 0.0;
  for (size_t p = 0; p < instanced.size(); ++p) {
    // readPixels' rows run top to bottom, glReadPixels' bottom to top.
    const size_t c = 4 * ((kSize - 1 - p / kSize) * kSize + p % kSize);
    const bool covered = colour[c] != background[c] || colour[c + 1] != background[c + 1] ||
                         colour[c + 2] != background[c + 2];
    const bool wrote = instanced[p] < 1.0f;
    written += wrote ? 1u : 0u;
    uncovered += covered != wrote ? 1u : 0u;
    if (wrote != (gpu_driven[p] < 1.0f))
      ++apart;
    else if (wrote)
      worst = std::max(worst, double(std::fabs(instanced[p] - gpu_driven[p])));
  }
  EXPECT_GT(written, 500u);
  // Pixels whose coverage test rounds otherwise at the threshold, as between the colour paths.
  EXPECT_LE(apart, written / 1000) << apart << " of " << written;
  EXPECT_LE(uncovered, written / 200) << uncovered << " of " << written;
  EXPECT_LT(worst, 1e-5);
}

// Impostors far enough to hold no pixel centre raster nothing: the GPU-driven path leaves their
// quads out (DrawStats::impostors_left_out) and draws the instanced path's image, which draws
// every quad; on a multisampled target, whose samples lie off the centres, none is left out.
TEST_P(RenderTest, ImpostorsThatHoldNoPixelCentreAreLeftOutOfTheSameImage) {
  CrowdManager crowd;
  initEveryOneAt(true, &crowd);
  // Rows from 20 to about 1,400 units along lodCamera()'s view: from a dozen pixels tall to a
  // fraction of one.
  uint32_t n = 0;
  for (int row = 0; row < 24; ++row)
    for (int k = 0; k < 12; ++k, ++n)
      addHeld(&crowd, glm::dvec3((k - 5.5) * (1.0 + 0.5 * row), 0.0, -20.0 * std::pow(1.2, row)),
              0.5f * float(k + row), n, 0.07 * n);
  ASSERT_TRUE(crowd.update(0.0, lodCamera()).isOk());
  Renderer r;
  CharacterId id;
  initImpostorRenderer(info_, true, &r, &id);
  DrawStats instanced;
  const std::vector<uint8_t> reference = draw(r, crowd, lodCamera(), 0, false, &instanced);
  r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
  DrawStats gpu;
  ASSERT_TRUE(r.drawCrowdGpuCulled(id, crowd.view(), lodCamera(), &gpu).isOk());
  std::vector<uint8_t> image;
  ASSERT_TRUE(context_->readPixels(&image).isOk());
  // The same pixels: the quads left out raster nothing (those of a pixel or two that do
  // raster draw a handful of pixels: exactness is what can see them).
  const Diff diff = compare(image, reference, nullptr);
  EXPECT_EQ(diff.share, 0.0) << "max channel difference " << diff.max_channel;
  EXPECT_GT(gpu.impostors_left_out, instanced.instances / 10) << instanced.instances;
  EXPECT_LT(gpu.impostors_left_out, instanced.instances / 2) << instanced.instances;
  EXPECT_EQ(gpu.instances + gpu.impostors_left_out, instanced.instances);
  EXPECT_EQ(gpu.triangles + 2 * gpu.impostors_left_out, instanced.triangles);
  EXPECT_EQ(instanced.impostors_left_out, 0u);
  // 4 samples a pixel: every quad drawn.
  TwoTargets multisampled(kSize, GL_RGBA8, 4);
  multisampled.clear();
  DrawStats samples;
  ASSERT_TRUE(r.drawCrowdGpuCulled(id, crowd.view(), lodCamera(), &samples).isOk());
  EXPECT_EQ(samples.impostors_left_out, 0u);
  EXPECT_EQ(samples.instances, instanced.instances);
}

// An impostor shows its clip's frames, so an instance holding a live pose is drawn as a mesh
// at the last mesh level where it would be an impostor, on the CPU's selection and in GPU-driven
// culling alike: the GPU-driven path draws the instanced path's image of a crowd whose far
// rows hold live poses.
TEST_P(RenderTest, LivePosesStayMeshesWhereTheirClipsWouldBeImpostors) {
  CrowdManager crowd, unposed;
  impostorCrowd(linesTo(60.0f), impostorLevels() - 1, &crowd, true);
  impostorCrowd(linesTo(60.0f), impostorLevels() - 1, &unposed);
  // The last two rows' 16 are past the line; 6 of them hold live poses (k = 1, 4, 7).
  const uint32_t* posed = crowd.view().stats().per_lod;
  const uint32_t* clips = unposed.view().stats().per_lod;
  ASSERT_EQ(clips[impostorLevels() - 1], 16u);
  EXPECT_EQ(posed[impostorLevels() - 1], 16u - 6u);
  EXPECT_EQ(posed[impostorLevels() - 2], clips[impostorLevels() - 2] + 6u);
  Renderer r;
  CharacterId id;
  initImpostorRenderer(info_, true, &r, &id);
  DrawStats reference_stats;
  const std::vector<uint8_t> reference = draw(r, crowd, lodCamera(), 0, false, &reference_stats);
  expectEveryCaseDraws({{"gpu-driven", &r, Path::kInstanced, true, DrawMode::kSkinned}}, crowd,
                       lodCamera(), reference, reference_stats);
}

TEST_P(RenderTest, AnImpostorAtItsHandOverHeightDiffersFromTheMeshByItsMeasuredError) {
  ImpostorDesc id = smallImpostor();
  ImageLodErrorDesc d;
  d.heights_pixels = {8, 16, 32};
  d.supersample = 1;  // As the test's images are drawn.
  d.azimuths = 8;
  d.azimuth_offset_degrees = 22.5f;  // Between the atlas's views,
  d.elevations_degrees = {10.0f};
  d.pose_phase = 0.37f;              // and between its frames.
  d.max_poses = 4;
  d.impostor = &id;
  ImageLodErrorReport report;
  Status s = measureImageLodErrors(info_, impostorCharacter(), palette(), d, &report);
  ASSERT_TRUE(s.isOk()) << s.toString();
  const ImageLodLevel& level = report.levels.back();
  ASSERT_EQ(level.mean_differing_pixels.size(), 3u);
  // It changes pixels, more when larger; the height where it changes one is finite.
  EXPECT_GT(level.mean_differing_pixels[2], level.mean_differing_pixels[0]);
  EXPECT_GT(level.one_pixel_height, 1.0);
  EXPECT_LT(level.one_pixel_height, 64.0);
  std::printf("[ impostor ] differing %.2f %.2f %.2f px at 8 16 32; one pixel at %.2f px\n",
              level.mean_differing_pixels[0], level.mean_differing_pixels[1],
              level.mean_differing_pixels[2], level.one_pixel_height);

  // The same character drawn 16 pixels tall by the crowd, from views and at times none of the
  // measured ones: as impostors and as meshes.
  Renderer r;
  impostorRenderer(info_, id, &r);
  const float height = impostorCharacter().height();
  const auto crowdAt = [&](bool impostors, CrowdManager* crowd) {
    initEveryOneAt(impostors, crowd);
    // 16 px tall at distance z: height / (2 z tan(fov / 2)) * 256 = 16.
    const double z = double(height) * 256.0 / (16.0 * 2.0 * std::tan(0.45));
    for (int k = 0; k < 6; ++k)
      addHeld(crowd, glm::dvec3((k - 2.5) * 0.25 * z * 0.3, -0.5 * height, -z),
              0.45f + 1.1f * float(k), uint32_t(k), 0.21 + 0.17 * k);
    ASSERT_TRUE(crowd->update(0.0, flatCamera()).isOk());
  };
  CrowdManager as_impostors, as_meshes;
  crowdAt(true, &as_impostors);
  crowdAt(false, &as_meshes);
  ASSERT_EQ(as_impostors.view().stats().per_lod[impostorLevels() - 1], 6u);
  ASSERT_EQ(as_meshes.view().stats().per_lod[0], 6u);
  const std::vector<uint8_t> a = draw(r, as_impostors, flatCamera(), 0);
  const std::vector<uint8_t> b = draw(r, as_meshes, flatCamera(), 0);
  const Diff diff = compare(a, b, nullptr);
  const double per_character = diff.share * kSize * kSize / 6.0;
  std::printf("[ impostor ] drawn 16 px tall: %.2f px differ per character (measured %.2f)\n",
              per_character, level.mean_differing_pixels[1]);
  EXPECT_GT(per_character, 0.0);
  // Within the measured error, with room for other views and times than the measured ones.
  EXPECT_LE(per_character, 2.0 * level.mean_differing_pixels[1] + 2.0);
}

// A camera straight above a character (top-down) sees it along its vertical axis, where the
// view has no azimuth: the impostor shows a captured cell turned as it was captured, so it
// draws what the mesh draws there (within the atlas's resolution), at every turn of the
// character, rather than a cell of an arbitrary azimuth turned another way.
TEST_P(RenderTest, ATopDownImpostorIsTurnedAsTheMesh) {
  ImpostorDesc id = smallImpostor();
  id.elevations_degrees = {0.0f, 45.0f, 90.0f};
  id.cell_pixels = 128;
  Renderer r;
  impostorRenderer(info_, id, &r);
  // The atlas's cell centre (buildImpostor's: every clip's bounds), straight below the camera.
  Aabb box = palette().clips[0].bounds;
  for (const BakedClip& clip : palette().clips) {
    box.min = glm::min(box.min, clip.bounds.min);
    box.max = glm::max(box.max, clip.bounds.max);
  }
  const glm::vec3 centre = 0.5f * (box.min + box.max);
  const float height = impostorCharacter().height();
  for (float turn : {0.0f, 0.7f, 2.0f}) {
    SCOPED_TRACE(turn);
    const glm::quat rotation = glm::angleAxis(turn, glm::vec3(0, 1, 0));
    const glm::dvec3 below = -glm::dvec3(rotation * centre);  // The centre at the origin.
    // Far and narrow (the quad's one depth barely matters): 1.5 heights across the image.
    const Camera above = Camera::lookAt({0.0, 30.0 * height, 0.0}, {0.0, 0.0, 0.0},
                                        glm::vec3(0, 0, -1), 0.05f, 1.0f, 1.0f, 100.0f * height);
    const auto crowdAt = [&](bool impostors, CrowdManager* crowd) {
      initEveryOneAt(impostors, crowd);
      InstanceDesc inst;
      inst.position = below;
      inst.rotation = rotation;
      inst.clip = uint32_t(palette().findClip("walk"));
      inst.speed = 0.0f;
      inst.variation_mask = 0xFFFFFFFFu;
      InstanceHandle h;
      ASSERT_TRUE(crowd->add(inst, &h).isOk());
      ASSERT_TRUE(crowd->update(0.0, above).isOk());
    };
    CrowdManager as_impostor, as_mesh;
    crowdAt(true, &as_impostor);
    crowdAt(false, &as_mesh);
    ASSERT_EQ(as_impostor.view().stats().per_lod[impostorLevels() - 1], 1u);
    const std::vector<uint8_t> a = draw(r, as_impostor, above, 0);
    const std::vector<uint8_t> b = draw(r, as_mesh, above, 0);
    // Coverage (pixels off the background, the corner's colour), which the turn decides.
    const auto drawn = [](const std::vector<uint8_t>& image, size_t p) {
      for (size_t c = 0; c < 3; ++c)
        if (std::abs(int(image[p + c]) - int(image[c])) > 2) return true;
      return false;
    };
    size_t covered = 0, mismatched = 0;
    for (size_t p = 0; p < a.size(); p += 4) {
      covered += drawn(b, p);
      mismatched += drawn(a, p) != drawn(b, p);
    }
    std::printf("[ impostor ] top-down, turned %.1f: %zu of %zu covered pixels differ\n", turn,
                mismatched, covered);
    EXPECT_GT(covered, 1000u);
    EXPECT_LT(double(mismatched), 0.15 * double(covered));
  }
}

TEST_P(RenderTest, ImpostorsRefuseWhatTheyCannotDraw) {
  Renderer r;
  RendererDesc rd;
  rd.skinning_path = SkinningPath::kVertexShader;  // Nothing measured: the refusals are the test.
  ASSERT_TRUE(r.init(info_, rd).isOk());
  CharacterId cid;
  ASSERT_TRUE(r.addCharacter(impostorCharacter(), palette(), &cid).isOk());
  EXPECT_FALSE(r.hasImpostor(cid));
  ImpostorDesc bad = smallImpostor();
  bad.elevations_degrees = {0, 10, 20, 30, 40};
  EXPECT_EQ(r.buildImpostor(cid, bad).code(), StatusCode::kInvalidArgument);
  bad.elevations_degrees = {30, 10};
  EXPECT_EQ(r.buildImpostor(cid, bad).code(), StatusCode::kInvalidArgument);
  bad = smallImpostor();
  bad.variation_mask = 0x100u;  // None of the 4 sub-meshes.
  EXPECT_EQ(r.buildImpostor(cid, bad).code(), StatusCode::kInvalidArgument);
  bad = smallImpostor();
  bad.cell_pixels = 1u << 20;
  EXPECT_EQ(r.buildImpostor(cid, bad).code(), StatusCode::kLimitExceeded);
  EXPECT_EQ(r.buildImpostor(CharacterId{7}, smallImpostor()).code(), StatusCode::kInvalidArgument);
  EXPECT_FALSE(r.hasImpostor(cid));
  // Past 2^20 cells (one capture instance each), within every side limit.
  bad = smallImpostor();
  bad.azimuths = 300000;
  bad.cell_pixels = 1;
  Status s = r.buildImpostor(cid, bad);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("1048576 instances"), std::string::npos) << s.message();
  // Past the byte budget: refused before allocating, with the plan reported; the plan is what
  // a build within the budget makes.
  ImpostorInfo planned, built;
  bad = smallImpostor();
  bad.max_bytes = 4096;
  s = r.buildImpostor(cid, bad, &planned);
  EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
  EXPECT_NE(s.message().find("max_bytes"), std::string::npos) << s.message();
  EXPECT_FALSE(r.hasImpostor(cid));
  EXPECT_GT(planned.bytes, 4096u);
  EXPECT_EQ(planned.capture_bytes, uint64_t(planned.width) * planned.height * 4);
  bad.max_bytes = planned.bytes + planned.capture_bytes;
  ASSERT_TRUE(r.buildImpostor(cid, bad, &built).isOk());
  EXPECT_EQ(built.bytes, planned.bytes);
  EXPECT_EQ(built.width, planned.width);
  EXPECT_EQ(built.cells, planned.cells);
  // A side past the renderbuffer or viewport limit (lowered, as a smaller GPU's) is refused by
  // name, not clamped into empty cells; the atlas built before stays.
  for (const char* limit : {"GL_MAX_RENDERBUFFER_SIZE", "GL_MAX_VIEWPORT_DIMS"}) {
    GlInfo small = info_;
    (std::string(limit) == "GL_MAX_RENDERBUFFER_SIZE" ? small.max_renderbuffer_size
                                                      : small.max_viewport_height) =
        planned.height - 1;
    Renderer lowered;
    ASSERT_TRUE(lowered.init(small, rd).isOk());
    CharacterId lid;
    ASSERT_TRUE(lowered.addCharacter(impostorCharacter(), palette(), &lid).isOk());
    s = lowered.buildImpostor(lid, smallImpostor());
    EXPECT_EQ(s.code(), StatusCode::kLimitExceeded);
    EXPECT_NE(s.message().find(limit), std::string::npos) << s.message();
    lowered.shutdown();
  }
  EXPECT_TRUE(r.hasImpostor(cid));

  CrowdManager crowd;
  impostorCrowd(linesTo(60.0f), impostorLevels() - 1, &crowd);
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  DrawStats stats;
  ASSERT_TRUE(r.replaceCharacter(cid, impostorCharacter(), palette()).isOk());  // Drops it.
  // No atlas yet.
  EXPECT_EQ(r.drawCrowd(CharacterId{}, crowd.view(), batcher, lodCamera(), &stats).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), lodCamera(), &stats).code(),
            StatusCode::kInvalidArgument);
  ASSERT_TRUE(r.buildImpostor(cid, smallImpostor()).isOk());
  EXPECT_TRUE(r.drawCrowd(CharacterId{}, crowd.view(), batcher, lodCamera(), &stats).isOk());
  // The baselines draw meshes only; impostors draw no motion vectors.
  EXPECT_EQ(r.drawTraditional(CharacterId{}, crowd.view(), lodCamera(), &stats).code(),
            StatusCode::kUnsupported);
  EXPECT_EQ(r.drawCpuSkinned(CharacterId{}, crowd.view(), lodCamera(), &stats).code(),
            StatusCode::kUnsupported);
  r.setMotionVectors(true);
  EXPECT_EQ(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), lodCamera(), &stats).code(),
            StatusCode::kUnsupported);
}

}  // namespace
}  // namespace si
