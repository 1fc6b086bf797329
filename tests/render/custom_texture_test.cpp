// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The per-instance custom texture (Renderer::setCustomTextureArray, InstanceDesc::custom_layer):
// a golden image, every drawing path equal, selects that must draw as none, and the refusals;
// each on desktop GL and on the OpenGL ES profile (EsCustomTextureTest: its one path).
#include <glad/gl.h>

#include "render/render_fixture.h"

namespace si {
namespace {

using namespace test;

constexpr int kLayerSize = 32;
constexpr int kLayers = 4;

// An application's texture array: layer l has stripes of two colours, 2 << l texels wide; layer
// 3 is transparent on every other stripe (the base texel shows through there). Nearest filter.
GLuint makeCustomArray() {
  GLuint t = 0;
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &t);
  glTextureStorage3D(t, 1, GL_RGBA8, kLayerSize, kLayerSize, kLayers);
  const uint8_t colours[kLayers][2][3] = {{{250, 250, 40}, {20, 20, 200}},
                                          {{240, 40, 40}, {250, 250, 250}},
                                          {{30, 200, 60}, {10, 10, 10}},
                                          {{250, 120, 0}, {0, 0, 0}}};
  std::vector<uint8_t> texels(size_t(kLayerSize) * kLayerSize * 4);
  for (int l = 0; l < kLayers; ++l) {
    for (int y = 0; y < kLayerSize; ++y)
      for (int x = 0; x < kLayerSize; ++x) {
        const int stripe = ((x + y) / (2 << l)) & 1;
        uint8_t* p = &texels[(size_t(y) * kLayerSize + x) * 4];
        for (int c = 0; c < 3; ++c) p[c] = colours[l][stripe][c];
        p[3] = l == 3 && stripe == 1 ? 0 : 255;
      }
    glTextureSubImage3D(t, 0, 0, 0, l, kLayerSize, kLayerSize, 1, GL_RGBA, GL_UNSIGNED_BYTE,
                        texels.data());
  }
  glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_REPEAT);
  return t;
}

Camera rowCamera() {
  return Camera::lookAt({0.0, 1.0, 4.6}, {0.0, 0.9, 0.0}, glm::vec3(0, 1, 0), 0.8f, 1.0f, 0.1f,
                        100.0f);
}

// Six characters in a row selecting no layer, layers 0-3 (selects 1-4) and select 77 (past the
// array: none); white and coloured tints.
std::vector<InstanceHandle> populateRow(CrowdManager* crowd) {
  const uint8_t selects[6] = {0, 1, 2, 3, 4, 77};
  const glm::u8vec4 tints[6] = {{255, 255, 255, 255}, {255, 255, 255, 255}, {120, 200, 255, 255},
                                {255, 255, 255, 255}, {255, 180, 120, 255}, {200, 255, 200, 255}};
  std::vector<InstanceHandle> handles;
  for (int k = 0; k < 6; ++k) {
    InstanceDesc d;
    d.position = glm::dvec3((k - 2.5) * 0.75, 0.0, 0.0);
    d.clip = uint32_t(palette().findClip("walk"));
    d.time_seconds = 0.1 * k;
    d.speed = 0.0f;
    d.color = tints[k];
    d.custom_layer = selects[k];
    InstanceHandle h;
    EXPECT_TRUE(crowd->add(d, &h).isOk());
    handles.push_back(h);
  }
  return handles;
}

template <bool kEs>
class CustomTextureScenes : public RenderTest {
 protected:
  bool es() const override { return kEs; }

  std::vector<uint8_t> drawGpuCulled(Renderer& r, const CrowdManager& crowd, DrawMode mode) {
    r.clear(glm::vec4(0.2f, 0.25f, 0.3f, 1.0f));
    const Status s = r.drawCrowdGpuCulled(CharacterId{}, crowd.view(), rowCamera(), nullptr, mode);
    EXPECT_TRUE(s.isOk()) << s.toString();
    std::vector<uint8_t> rgba;
    EXPECT_TRUE(context_->readPixels(&rgba).isOk());
    return rgba;
  }
  void customLayersGolden() {
    Renderer r;
    makeRenderer(&r);
    const GLuint array = makeCustomArray();
    ASSERT_TRUE(r.setCustomTextureArray(array).isOk());
    EXPECT_EQ(r.customTextureLayers(), uint32_t(kLayers));
    CrowdManager crowd;
    makeCrowd(&crowd);
    populateRow(&crowd);
    ASSERT_TRUE(crowd.update(0.0, rowCamera()).isOk());
    ASSERT_EQ(crowd.view().stats().visible, 6u);
    const std::vector<uint8_t> image = draw(r, crowd, rowCamera(), 0);
    expectGolden("custom_layers", image);
    if (kEs) {  // The ES profile's one path.
      r.shutdown();
      glDeleteTextures(1, &array);
      return;
    }
    // Every drawing path shades the custom layers the same way.
    const struct {
      const char* name;
      std::vector<uint8_t> rgba;
    } others[] = {
        {"compute", draw(r, crowd, rowCamera(), 0, false, nullptr, Path::kCompute)},
        {"traditional", draw(r, crowd, rowCamera(), 0, false, nullptr, Path::kTraditional)},
        {"CPU-skinned", draw(r, crowd, rowCamera(), 0, false, nullptr, Path::kCpuSkinned)},
        {"GPU-driven", drawGpuCulled(r, crowd, DrawMode::kSkinned)},
        {"GPU-driven compute", drawGpuCulled(r, crowd, DrawMode::kComputeSkinned)},
    };
    for (const auto& o : others) {
      const Diff d = compare(image, o.rgba, nullptr);
      EXPECT_LE(d.share, 0.001) << o.name << ": max channel difference " << d.max_channel;
    }
    r.shutdown();
    glDeleteTextures(1, &array);
  }

  void selectsShowTheirLayerAndNothingElse() {
    Renderer r;
    makeRenderer(&r);
    const GLuint array = makeCustomArray();
    ASSERT_TRUE(r.setCustomTextureArray(array).isOk());
    CrowdManager crowd;
    makeCrowd(&crowd);
    const std::vector<InstanceHandle> handles = populateRow(&crowd);
    ASSERT_TRUE(crowd.update(0.0, rowCamera()).isOk());
    const std::vector<uint8_t> custom = draw(r, crowd, rowCamera(), 0);
    // Every select 0: the base texture only.
    for (InstanceHandle h : handles) ASSERT_TRUE(crowd.setCustomLayer(h, 0).isOk());
    ASSERT_TRUE(crowd.update(0.0, rowCamera()).isOk());
    const std::vector<uint8_t> none = draw(r, crowd, rowCamera(), 0);
    const Diff changed = compare(custom, none, nullptr);
    EXPECT_GT(changed.share, 0.01) << "the custom layers changed too little of the image";
    // Select 77 of a 4-layer array draws as select 0: only the other instances' pixels differ.
    ASSERT_TRUE(crowd.setCustomLayer(handles[5], 77).isOk());
    ASSERT_TRUE(crowd.update(0.0, rowCamera()).isOk());
    EXPECT_EQ(compare(none, draw(r, crowd, rowCamera(), 0), nullptr).max_channel, 0);
    // Restoring the selects restores the image; detaching the array draws every select as none.
    for (size_t k = 0; k < handles.size(); ++k)
      ASSERT_TRUE(crowd.setCustomLayer(handles[k], uint8_t(k == 5 ? 77 : k)).isOk());
    ASSERT_TRUE(crowd.update(0.0, rowCamera()).isOk());
    EXPECT_EQ(compare(custom, draw(r, crowd, rowCamera(), 0), nullptr).max_channel, 0);
    ASSERT_TRUE(r.setCustomTextureArray(0).isOk());
    EXPECT_EQ(r.customTextureLayers(), 0u);
    EXPECT_EQ(compare(none, draw(r, crowd, rowCamera(), 0), nullptr).max_channel, 0);
    r.shutdown();
    glDeleteTextures(1, &array);
  }

  void refusesWhatIsNotATextureArrayAndKeepsThePrevious() {
    Renderer r;
    EXPECT_EQ(r.setCustomTextureArray(1).code(), StatusCode::kInvalidArgument);  // No init.
    makeRenderer(&r);
    const GLuint array = makeCustomArray();
    ASSERT_TRUE(r.setCustomTextureArray(array).isOk());
    GLuint plain = 0, empty = 0, big = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &plain);
    glTextureStorage2D(plain, 1, GL_RGBA8, 4, 4);
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &empty);  // No storage.
    const Status not_a_name = r.setCustomTextureArray(987654);
    EXPECT_EQ(not_a_name.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(not_a_name.message().find("not a texture"), std::string::npos)
        << not_a_name.message();
    const Status wrong_target = r.setCustomTextureArray(plain);
    EXPECT_EQ(wrong_target.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(wrong_target.message().find("GL_TEXTURE_2D,"), std::string::npos)
        << wrong_target.message();
    EXPECT_EQ(r.setCustomTextureArray(empty).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(r.customTextureLayers(), uint32_t(kLayers));  // The previous array stays.
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    // More layers than a select reaches: the first 255 are selectable.
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &big);
    glTextureStorage3D(big, 1, GL_RGBA8, 1, 1, 300);
    ASSERT_TRUE(r.setCustomTextureArray(big).isOk());
    EXPECT_EQ(r.customTextureLayers(), kMaxCustomLayers);
    r.shutdown();
    const GLuint textures[] = {array, plain, empty, big};
    glDeleteTextures(4, textures);
  }
};

using CustomTextureTest = CustomTextureScenes<false>;
using EsCustomTextureTest = CustomTextureScenes<true>;
#define SI_CUSTOM_TEXTURE_TESTS(Fixture)                              \
  TEST_P(Fixture, CustomLayersGolden) {                               \
    customLayersGolden();                                             \
  }                                                                   \
  TEST_P(Fixture, SelectsShowTheirLayerAndNothingElse) {              \
    selectsShowTheirLayerAndNothingElse();                            \
  }                                                                   \
  TEST_P(Fixture, RefusesWhatIsNotATextureArrayAndKeepsThePrevious) { \
    refusesWhatIsNotATextureArrayAndKeepsThePrevious();               \
  }
SI_CUSTOM_TEXTURE_TESTS(CustomTextureTest)
SI_CUSTOM_TEXTURE_TESTS(EsCustomTextureTest)

INSTANTIATE_TEST_SUITE_P(Backends, CustomTextureTest, test::allBackends(),
                         test::backendTestName);
INSTANTIATE_TEST_SUITE_P(Backends, EsCustomTextureTest, test::esBackends(), test::backendTestName);

}  // namespace
}  // namespace si
