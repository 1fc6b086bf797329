// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The image error per LOD level (si::measureImageLodErrors): zero for a level that draws LOD 0's
// triangles, growing with the height and the level for the embedded character's real levels,
// the equivalent units where one pixel changes; the host's framebuffer and viewport kept; bad
// input refused.
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <vector>

#include "render/render_fixture.h"
#include "si/gl/image_lod_error.h"

namespace si {
namespace {

using namespace test;

ImageLodErrorDesc smallDesc() {
  ImageLodErrorDesc d;
  d.heights_pixels = {8, 16, 32};
  d.azimuths = 4;
  d.elevations_degrees = {0.0f, 40.0f};
  d.max_poses = 3;
  return d;
}

TEST_P(RenderTest, ImageLodErrorsGrowWithTheLevelAndTheHeight) {
  // The host's framebuffer (the context's own, not 0) and a viewport that must survive the call.
  using GetIntegervFn = void (*)(unsigned, int*);
  using ViewportFn = void (*)(int, int, int, int);
  auto get = reinterpret_cast<GetIntegervFn>(
      HeadlessContext::getProcAddress(context_.get(), "glGetIntegerv"));
  auto viewport = reinterpret_cast<ViewportFn>(
      HeadlessContext::getProcAddress(context_.get(), "glViewport"));
  constexpr unsigned kDrawBinding = 0x8CA6, kReadBinding = 0x8CAA, kViewport = 0x0BA2;
  viewport(3, 5, 17, 19);
  int draw_before = -1, read_before = -1;
  get(kDrawBinding, &draw_before);
  get(kReadBinding, &read_before);
  ImageLodErrorReport r;
  const Status s = measureImageLodErrors(info_, character(), palette(), smallDesc(), &r);
  ASSERT_TRUE(s.isOk()) << s.toString();
  int draw = -1, read = -1, box[4] = {};
  get(kDrawBinding, &draw);
  get(kReadBinding, &read);
  get(kViewport, box);
  EXPECT_EQ(draw, draw_before);
  EXPECT_EQ(read, read_before);
  EXPECT_EQ(box[0], 3);
  EXPECT_EQ(box[1], 5);
  EXPECT_EQ(box[2], 17);
  EXPECT_EQ(box[3], 19);

  ASSERT_EQ(r.levels.size(), character().mesh.maxLodCount());
  EXPECT_EQ(r.poses, 3u);
  EXPECT_EQ(r.views, 8u);
  EXPECT_EQ(r.levels[0].image_units, 0.0f);
  for (size_t l = 1; l < r.levels.size(); ++l) {
    const ImageLodLevel& level = r.levels[l];
    ASSERT_EQ(level.mean_differing_pixels.size(), 3u);
    // A simplified level changes pixels, more at larger heights, never more than the cells hold.
    EXPECT_GT(level.mean_differing_pixels[2], level.mean_differing_pixels[0]) << l;
    EXPECT_GE(level.max_differing_pixels[2], level.mean_differing_pixels[2]);
    EXPECT_LT(level.max_differing_pixels[2], 48.0 * 48.0);
    // One pixel changes between the measured heights or past them; the units follow.
    EXPECT_GT(level.one_pixel_height, 0.0);
    EXPECT_NEAR(level.image_units, r.character_height_units / level.one_pixel_height, 1e-4);
  }
  // Coarser levels change more (at the largest height).
  EXPECT_GT(r.levels.back().mean_differing_pixels[2], r.levels[1].mean_differing_pixels[2]);
  const std::vector<float> units = imageLodErrorsUnits(r);
  for (size_t l = 1; l < units.size(); ++l) EXPECT_GE(units[l], units[l - 1]);
}

// The embedded character with its level 1 drawing LOD 0's own triangles.
Character levelOneAsLodZero() {
  Character same = test::character();
  for (SubMesh& sm : same.mesh.sub_meshes) {
    sm.lods[1] = sm.lods[0];
    sm.lod_error_units[1] = 0.0f;
  }
  return same;
}

// A level drawing LOD 0's own triangles changes no pixel: its image error is 0 at every height.
TEST_P(RenderTest, ALevelEqualToLodZeroHasNoImageError) {
  const Character same = levelOneAsLodZero();
  ImageLodErrorReport r;
  ASSERT_TRUE(measureImageLodErrors(info_, same, palette(), smallDesc(), &r).isOk());
  for (double px : r.levels[1].mean_differing_pixels) EXPECT_EQ(px, 0.0);
  EXPECT_TRUE(std::isinf(r.levels[1].one_pixel_height));
  EXPECT_EQ(r.levels[1].image_units, 0.0f);
  EXPECT_GT(r.levels[2].mean_differing_pixels[2], 0.0);
}

// Measured through a material (ImageLodErrorDesc::material), the error is the one its image
// shows: a material colouring each level apart makes that same level differ at every pixel.
TEST_P(RenderTest, ImageLodErrorsAreMeasuredThroughTheMaterial) {
  const Character same = levelOneAsLodZero();
  MaterialDesc by_level;
  by_level.name = "colour by level";
  by_level.source = R"(
layout(location = 0) out vec4 o_colour;
void siMaterial(SiSurface s) { o_colour = vec4(s.lod == 0u ? 1.0 : 0.0, 0.5, 0.5, 1.0); })";
  ImageLodErrorDesc d = smallDesc();
  d.material = &by_level;
  ImageLodErrorReport r;
  const Status s = measureImageLodErrors(info_, same, palette(), d, &r);
  ASSERT_TRUE(s.isOk()) << s.toString();
  // Every covered pixel of level 1 (a character 32 pixels tall covers far more than 20).
  EXPECT_GT(r.levels[1].mean_differing_pixels[2], 20.0);
  EXPECT_GT(r.levels[1].image_units, 0.0f);
  MaterialDesc broken = by_level;
  broken.source = "void siMaterial(SiSurface s) { undeclared(); }";
  d.material = &broken;
  EXPECT_EQ(measureImageLodErrors(info_, same, palette(), d, &r).code(), StatusCode::kBackend);
}

TEST_P(RenderTest, ImageLodErrorsRefuseBadInput) {
  ImageLodErrorReport r;
  r.character_height_units = 7.0f;
  EXPECT_EQ(measureImageLodErrors(info_, character(), palette(), {}, nullptr).code(),
            StatusCode::kInvalidArgument);
  ImageLodErrorDesc zero = smallDesc();
  zero.heights_pixels = {8, 0};
  EXPECT_EQ(measureImageLodErrors(info_, character(), palette(), zero, &r).code(),
            StatusCode::kInvalidArgument);
  ImageLodErrorDesc huge = smallDesc();
  huge.heights_pixels = {100000};
  EXPECT_EQ(measureImageLodErrors(info_, character(), palette(), huge, &r).code(),
            StatusCode::kLimitExceeded);
  BakedPalette empty = palette();
  empty.clips.clear();
  EXPECT_EQ(measureImageLodErrors(info_, character(), empty, smallDesc(), &r).code(),
            StatusCode::kInvalidArgument);
  Character no_errors = character();
  for (SubMesh& sm : no_errors.mesh.sub_meshes) sm.lod_error_units.clear();
  EXPECT_EQ(measureImageLodErrors(info_, no_errors, palette(), smallDesc(), &r).code(),
            StatusCode::kInvalidArgument);
  EXPECT_EQ(r.character_height_units, 7.0f);  // Nothing written.
}

// Non-decreasing; with an impostor, the mesh levels whose error exceeds the impostor's take
// its error (the choice skips them), and the impostor keeps its own.
// A report of levels with these image errors (nothing else measured).
ImageLodErrorReport reportOf(std::initializer_list<float> image_units) {
  ImageLodErrorReport r;
  for (float units : image_units) {
    ImageLodLevel level;
    level.image_units = units;
    r.levels.push_back(level);
  }
  return r;
}

TEST(ImageLodErrors, UnitsAreNonDecreasingAndSkipLevelsTheImpostorDominates) {
  ImageLodErrorReport r = reportOf({0.0f, 0.3f, 0.2f, 0.8f, 0.9f, 0.6f});
  EXPECT_EQ(imageLodErrorsUnits(r), (std::vector<float>{0.0f, 0.3f, 0.3f, 0.8f, 0.9f, 0.9f}));
  r.impostor = true;
  EXPECT_EQ(imageLodErrorsUnits(r), (std::vector<float>{0.0f, 0.3f, 0.3f, 0.6f, 0.6f, 0.6f}));
  r.levels.back().image_units = 1.5f;  // Worse than every mesh level: handed over last.
  EXPECT_EQ(imageLodErrorsUnits(r), (std::vector<float>{0.0f, 0.3f, 0.3f, 0.8f, 0.9f, 1.5f}));
}

// Geometric errors with an impostor: the trailing mesh levels it beats in image error hand over
// to it at the first one's geometric error; none beaten: after the last mesh level.
TEST(ImageLodErrors, ImpostorTakesOverFromTheMeshLevelsItBeats) {
  ImageLodErrorReport r = reportOf({0.0f, 0.24f, 0.57f, 0.80f, 0.90f, 0.63f});
  const std::vector<float> geometric = {0.0f, 0.027f, 0.1f, 0.26f, 0.85f, 0.85f};
  EXPECT_EQ(impostorLodErrorsUnits(geometric, r), geometric);  // Not an impostor report.
  r.impostor = true;
  EXPECT_EQ(impostorLodErrorsUnits(geometric, r),
            (std::vector<float>{0.0f, 0.027f, 0.1f, 0.26f, 0.26f, 0.26f}));
  r.levels.back().image_units = 0.95f;  // Beats none: after LOD 4, at its own error if larger.
  EXPECT_EQ(impostorLodErrorsUnits(geometric, r),
            (std::vector<float>{0.0f, 0.027f, 0.1f, 0.26f, 0.85f, 0.95f}));
  r.levels.back().image_units = 0.1f;  // Beats every mesh level past LOD 0.
  EXPECT_EQ(impostorLodErrorsUnits(geometric, r),
            (std::vector<float>{0.0f, 0.027f, 0.027f, 0.027f, 0.027f, 0.027f}));
  EXPECT_EQ(impostorLodErrorsUnits({0.0f, 1.0f}, r), (std::vector<float>{0.0f, 1.0f}));  // Counts.
}

// Each element of `got` within 1e-3 of `want`'s.
void expectNear(const std::vector<float>& got, const std::vector<float>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (size_t k = 0; k < got.size(); ++k) EXPECT_NEAR(got[k], want[k], 1e-3f) << "level " << k;
}

// The embedded character's curves (H100, docs/accuracy.md: mean differing pixels at 8, 16 and
// 64 px) with an impostor whose one-pixel height is greater than LOD 2's but whose error grows
// faster (a finer atlas's shape). Compared by one number it would take every character of LOD
// 2's (up to 2.04 / 0.1 = 20.4 px at a 1-pixel budget); its curve crosses LOD 2's at 12.87 px
// (3 (h / 8)^3.32 = 5.9 (h / 8)^1.90), so it takes the characters up to there: it takes over at
// 2.04 / 12.87 = 0.1585 units. At half a pixel LOD 2's characters end at 10.2 px, below the
// crossing, and LOD 1's, above, change fewer pixels than it: it takes LOD 2's, at 0.1 units.
TEST(ImageLodErrors, ImpostorTakesTheCharactersUpToWhereItsCurveCrossesTheMeshLevels) {
  ImageLodErrorReport r;
  r.impostor = true;
  r.heights_pixels = {16, 8, 64};  // In any order.
  r.character_height_units = 2.04f;
  for (const std::vector<double>& curve : std::vector<std::vector<double>>{{0.0, 0.0, 0.0},
                                                                           {4.8, 0.88, 112.0},
                                                                           {22.0, 5.9, 354.0},
                                                                           {45.0, 12.0, 650.0},
                                                                           {45.0, 13.0, 586.0},
                                                                           {30.0, 3.0, 600.0}}) {
    ImageLodLevel level;
    level.mean_differing_pixels = curve;
    r.levels.push_back(level);
  }
  r.levels[1].image_units = 0.24f;  // As measureImageLodErrors derives them from the curves.
  r.levels[2].image_units = 0.65f;
  r.levels[3].image_units = 0.80f;
  r.levels[4].image_units = 0.90f;
  r.levels[5].image_units = 0.36f;
  const std::vector<float> geometric = {0.0f, 0.027f, 0.1f, 0.26f, 0.85f, 0.85f};
  const std::vector<float> crossing = {0.0f, 0.027f, 0.1f, 0.1585f, 0.1585f, 0.1585f};
  const std::vector<float> from_lod2 = {0.0f, 0.027f, 0.1f, 0.1f, 0.1f, 0.1f};
  expectNear(impostorLodErrorsUnits(geometric, r), crossing);
  expectNear(impostorLodErrorsUnits(geometric, r, 1.0f), crossing);
  EXPECT_EQ(impostorLodErrorsUnits(geometric, r, 0.5f), from_lod2);  // Exactly LOD 2's error.
  for (float meaningless : {0.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(),
                            std::numeric_limits<float>::infinity()})
    expectNear(impostorLodErrorsUnits(geometric, r, meaningless), crossing);
  // The default atlas's curve (9.5, 45, 645 at 8, 16, 64 px) wins up to LOD 3's last height
  // (7.85 px) and loses to LOD 2 from there: it takes over at LOD 3's error, as before.
  ImageLodErrorReport coarse = r;
  coarse.levels[5].mean_differing_pixels = {45.0, 9.5, 645.0};
  coarse.levels[5].image_units = 0.63f;
  EXPECT_EQ(impostorLodErrorsUnits(geometric, coarse),
            (std::vector<float>{0.0f, 0.027f, 0.1f, 0.26f, 0.26f, 0.26f}));
  // One that loses to LOD 4 from 1 pixel on comes after it, at its one-pixel error.
  ImageLodErrorReport worse = r;
  worse.levels[5].mean_differing_pixels = {90.0, 30.0, 900.0};
  worse.levels[5].image_units = 1.5f;
  EXPECT_EQ(impostorLodErrorsUnits(geometric, worse),
            (std::vector<float>{0.0f, 0.027f, 0.1f, 0.26f, 0.85f, 1.5f}));
  // Without curves the one-pixel heights are compared: the fine impostor takes LOD 2's.
  ImageLodErrorReport no_curves = r;
  no_curves.heights_pixels.clear();
  EXPECT_EQ(impostorLodErrorsUnits(geometric, no_curves), from_lod2);
}

// Hostile reports (what a host could hand-build or corrupt): the hand-over returns one error
// per level, non-decreasing wherever it is finite, without hanging or reading past a vector.
TEST(ImageLodErrors, TheHandOverSurvivesHostileReports) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> geometric = {0.0f, 0.027f, 0.1f, 0.26f, 0.85f, 0.85f};
  const std::vector<std::vector<uint32_t>> heights = {
      {0, 8, 16}, {8, 8, 8}, {4, 8, 0xFFFFFFFFu}, {1}, {16, 8, 4}};
  const std::vector<std::vector<double>> curves = {
      {0.0, 0.0, 0.0},         {1.0, 1.0, 1.0},  {5.0, 1.0, 0.5},     {double(nan), 2.0, 3.0},
      {double(inf), 1.0, 2.0}, {-1.0, 2.0, 4.0}, {1e300, 1e-300, 1.0}};
  for (const std::vector<uint32_t>& h : heights)
    for (const std::vector<double>& impostor : curves)
      for (const std::vector<double>& mesh : curves)
        for (float height_units : {2.04f, 0.0f, nan, inf}) {
          ImageLodErrorReport r;
          r.impostor = true;
          r.heights_pixels = h;
          r.character_height_units = height_units;
          for (size_t l = 0; l < geometric.size(); ++l) {
            ImageLodLevel level;
            const std::vector<double>& c = l + 1 == geometric.size() ? impostor : mesh;
            level.mean_differing_pixels.assign(c.begin(), c.begin() + std::min(c.size(), h.size()));
            level.mean_differing_pixels.resize(h.size(), 1.0);
            level.image_units = l + 1 == geometric.size() ? 0.6f : 0.3f * float(l);
            r.levels.push_back(level);
          }
          for (float budget : {1.0f, 0.25f, 1e30f}) {
            const std::vector<float> out = impostorLodErrorsUnits(geometric, r, budget);
            ASSERT_EQ(out.size(), geometric.size());
            for (size_t l = 1; l < out.size(); ++l) {
              if (std::isfinite(out[l])) {
                EXPECT_GE(out[l], out[l - 1]) << l;
              }
            }
          }
        }
}

}  // namespace
}  // namespace si
