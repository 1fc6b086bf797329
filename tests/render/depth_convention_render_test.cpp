// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The engine's depth convention (si::DepthConvention): under glClipControl's zero-to-one depth
// and under reverse-Z with an infinite far plane, every path draws the standard camera's image
// and, converted back to distances along the view axis, its depth; two-phase occlusion culling
// culls the same instances under all three; a camera whose convention does not match the
// context's clip control is refused by name.
#include <glad/gl.h>

#include "render/depth_distances.h"
#include "render/render_fixture.h"

namespace si {
namespace {

using namespace test;

// The context's clip control, depth function and depth clear for `convention`.
struct DepthState {
  explicit DepthState(DepthConvention convention) {
    const bool zero_to_one = convention != DepthConvention::kNegativeOneToOne;
    reversed = convention == DepthConvention::kReversedZeroToOne;
    glClipControl(GL_LOWER_LEFT, zero_to_one ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE);
    glDepthFunc(reversed ? GL_GREATER : GL_LESS);
  }
  ~DepthState() {
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glDepthFunc(GL_LESS);
  }
  float clearDepth() const { return reversed ? 0.0f : 1.0f; }
  bool reversed = false;
};

std::vector<float> readDepth() {
  std::vector<float> z(size_t(kSize) * kSize);
  glReadPixels(0, 0, GLsizei(kSize), GLsizei(kSize), GL_DEPTH_COMPONENT, GL_FLOAT, z.data());
  return z;
}

class DepthConventionTest : public RenderTest {
 protected:
  // Clears (colour and `clear_depth`) and draws `crowd` with `camera` on `kind`; the image.
  std::vector<uint8_t> drawKind(Renderer& r, PathKind kind, const CrowdManager& crowd,
                                const Camera& camera, float clear_depth, DrawStats* st) {
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f), clear_depth);
    const Status s = drawOnPath(r, kind, crowd, camera, st);
    EXPECT_TRUE(s.isOk()) << s.toString();
    std::vector<uint8_t> rgba;
    EXPECT_TRUE(context_->readPixels(&rgba).isOk());
    return rgba;
  }
};

TEST_P(DepthConventionTest, EveryPathDrawsTheStandardImageAndDepthUnderEveryConvention) {
  const float fov = 0.9f, near_plane = 0.1f, far_plane = 500.0f;
  const Camera standard = lodCamera();
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateLodCrowd(&crowd);
  addFadingCharacter(&crowd);
  ASSERT_TRUE(crowd.update(0.3, standard).isOk());
  Renderer r;
  makeRenderer(&r);
  DrawStats reference_stats;
  const std::vector<uint8_t> reference =
      drawKind(r, PathKind::kInstanced, crowd, standard, 1.0f, &reference_stats);
  const std::vector<float> reference_distance = viewDistances(readDepth(), standard);
  for (DepthConvention convention :
       {DepthConvention::kZeroToOne, DepthConvention::kReversedZeroToOne}) {
    SCOPED_TRACE(depthConventionName(convention));
    const Camera camera = withConvention(standard, convention, fov, near_plane, far_plane);
    CrowdManager seen;  // The same crowd selected by this camera: the same instances and LODs.
    makeCrowd(&seen);
    populateLodCrowd(&seen);
    addFadingCharacter(&seen);
    ASSERT_TRUE(seen.update(0.3, camera).isOk());
    EXPECT_EQ(seen.view().stats().visible, crowd.view().stats().visible);
    const DepthState state(convention);
    for (PathKind kind : kEveryPath) {
      SCOPED_TRACE(pathKindName(kind));
      DrawStats st;
      const std::vector<uint8_t> image = drawKind(r, kind, seen, camera, state.clearDepth(), &st);
      const Diff diff = compare(image, reference, nullptr);
      EXPECT_LE(diff.share, 0.001) << "max channel difference " << diff.max_channel;
      const DistanceDiff d =
          compareDistances(viewDistances(readDepth(), camera), reference_distance);
      const size_t covered = d.covered, apart = d.apart;
      EXPECT_GT(covered, 2000u);
      EXPECT_LE(apart, covered / 200) << apart << " of " << covered;
    }
  }
}

TEST_P(DepthConventionTest, OcclusionCullsTheSameInstancesUnderEveryConvention) {
  const Camera standard = wallCamera();
  CrowdManager crowd;
  makeCoarseCrowd(&crowd);
  populateWallCrowd(&crowd);
  std::vector<DrawStats> culled;
  std::vector<std::vector<uint8_t>> images;
  for (DepthConvention convention :
       {DepthConvention::kNegativeOneToOne, DepthConvention::kZeroToOne,
        DepthConvention::kReversedZeroToOne}) {
    SCOPED_TRACE(depthConventionName(convention));
    const Camera camera = withConvention(standard, convention, 0.9f, 0.1f, 500.0f);
    const DepthState state(convention);
    RendererDesc rd;
    rd.skinning_path = SkinningPath::kVertexShader;
    rd.gpu_occlusion_culling = true;
    rd.measure_gpu_time = true;  // Reads back the counts.
    Renderer r;
    makeRenderer(&r, 0, PaletteFormat::kMatrix3x4F32, &rd);
    DrawStats st;
    std::vector<uint8_t> image;
    for (int frame = 0; frame < 3; ++frame)  // Frame 2 knows what frame 1 found hidden.
      image = drawKind(r, PathKind::kGpuDriven, crowd, camera, state.clearDepth(), &st);
    // Most of the crowd behind the wall is culled, its front row drawn.
    EXPECT_LT(st.gpu_visible, 400u);
    EXPECT_GE(st.gpu_visible, 40u);
    culled.push_back(st);
    images.push_back(image);
  }
  for (size_t k = 1; k < culled.size(); ++k) {
    EXPECT_EQ(culled[k].gpu_visible, culled[0].gpu_visible) << k;
    EXPECT_EQ(culled[k].triangles, culled[0].triangles) << k;
    EXPECT_LE(compare(images[k], images[0], nullptr).share, 0.001) << k;
  }
}

TEST_P(DepthConventionTest, ACameraOfAnotherConventionThanTheClipControlIsRefusedByName) {
  Renderer r;
  makeRenderer(&r);
  CrowdManager crowd;
  makeCrowd(&crowd);
  populateLodCrowd(&crowd);
  const Camera reversed =
      withConvention(lodCamera(), DepthConvention::kReversedZeroToOne, 0.9f, 0.1f, 500.0f);
  ASSERT_TRUE(crowd.update(0.0, reversed).isOk());
  InstanceBatcher batcher;
  ASSERT_TRUE(batcher.init(r.batchLimits()).isOk());
  const auto refused = [](const Status& s, const char* mode) {
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << s.toString();
    EXPECT_NE(s.message().find(std::string("clip control depth mode is ") + mode),
              std::string::npos)
        << s.message();
  };
  refused(r.drawCrowd(CharacterId{}, crowd.view(), batcher, reversed, nullptr),
          "GL_NEGATIVE_ONE_TO_ONE");
  refused(r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), reversed, nullptr),
          "GL_NEGATIVE_ONE_TO_ONE");
  refused(r.drawTraditional(CharacterId{}, crowd.view(), reversed, nullptr),
          "GL_NEGATIVE_ONE_TO_ONE");
  refused(r.drawCpuSkinned(CharacterId{}, crowd.view(), reversed, nullptr),
          "GL_NEGATIVE_ONE_TO_ONE");
  {
    const DepthState state(DepthConvention::kZeroToOne);
    refused(r.drawCrowd(CharacterId{}, crowd.view(), batcher, lodCamera(), nullptr),
            "GL_ZERO_TO_ONE");
    EXPECT_TRUE(r.drawCrowd(CharacterId{}, crowd.view(), batcher, reversed, nullptr).isOk());
  }
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

INSTANTIATE_TEST_SUITE_P(Backends, DepthConventionTest, allBackends(), backendTestName);

}  // namespace
}  // namespace si
