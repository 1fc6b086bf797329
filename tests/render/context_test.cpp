// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// Offscreen contexts through each back-end: create, load GL, clear, read back, write a PNG.
// Skips with a printed reason when no context exists; SI_REQUIRE_GL (a list of back-end names,
// set by scripts/test.sh in CI) turns that skip into a failure for the back-ends it names.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstdio>

#include "si/gl/gl_context.h"
#include "render/render_test_helpers.h"
#include "si/headless/headless_context.h"

namespace si {
namespace {

using test::requireGl;

class ContextTest : public ::testing::TestWithParam<HeadlessBackend> {};

// Loaded by name so this test does not need a GL header.
using ClearColorFn = void (*)(float, float, float, float);
using ClearFn = void (*)(unsigned);
constexpr unsigned kColorBufferBit = 0x00004000;

TEST_P(ContextTest, CreatesLoadsClearsAndReadsBack) {
  HeadlessDesc d;
  d.width = 64;
  d.height = 32;
  d.backend = GetParam();
  std::unique_ptr<HeadlessContext> ctx;
  const Status s = HeadlessContext::create(d, &ctx);
  if (!s.isOk()) {
    if (requireGl(GetParam())) FAIL() << s.toString();
    GTEST_SKIP() << "no " << headlessBackendName(GetParam()) << " context: " << s.message();
  }
  EXPECT_EQ(ctx->backend(), GetParam());
  EXPECT_EQ(ctx->width(), 64u);
  GlInfo info;
  ASSERT_TRUE(loadGl(&HeadlessContext::getProcAddress, ctx.get(), &info).isOk());
  std::printf("[ context  ] %s: %s, GL %s, max UBO %u bytes, UBO alignment %u\n",
              headlessBackendName(ctx->backend()), info.renderer.c_str(), info.version.c_str(),
              info.max_uniform_block_size_bytes, info.uniform_buffer_offset_alignment);
  EXPECT_GE(info.max_uniform_block_size_bytes, 16384u);  // GL's minimum.
  EXPECT_GT(info.uniform_buffer_offset_alignment, 0u);
  EXPECT_GE(info.max_texture_size, 1024u);
  auto clear_color = reinterpret_cast<ClearColorFn>(
      HeadlessContext::getProcAddress(ctx.get(), "glClearColor"));
  auto clear = reinterpret_cast<ClearFn>(HeadlessContext::getProcAddress(ctx.get(), "glClear"));
  ASSERT_NE(clear_color, nullptr);
  clear_color(1.0f, 0.5f, 0.0f, 1.0f);
  clear(kColorBufferBit);
  EXPECT_TRUE(checkGlErrors("clear").isOk());
  std::vector<uint8_t> rgba;
  ASSERT_TRUE(ctx->readPixels(&rgba).isOk());
  ASSERT_EQ(rgba.size(), 64u * 32u * 4u);
  EXPECT_EQ(rgba[0], 255);
  EXPECT_NEAR(rgba[1], 128, 1);
  EXPECT_EQ(rgba[2], 0);
  EXPECT_EQ(rgba[3], 255);
  const std::string path = ::testing::TempDir() + "si_context_test.png";
  ASSERT_TRUE(writePng(path, 64, 32, rgba).isOk());
  uint32_t w = 0, h = 0;
  std::vector<uint8_t> back;
  ASSERT_TRUE(readPng(path, &w, &h, &back).isOk());
  EXPECT_EQ(back, rgba);
  std::remove(path.c_str());
  // makeCurrent() binds the context's framebuffer again, as its documentation says.
  using BindFramebufferFn = void (*)(unsigned, unsigned);
  using GetIntegervFn = void (*)(unsigned, int*);
  auto bind = reinterpret_cast<BindFramebufferFn>(
      HeadlessContext::getProcAddress(ctx.get(), "glBindFramebuffer"));
  auto get = reinterpret_cast<GetIntegervFn>(
      HeadlessContext::getProcAddress(ctx.get(), "glGetIntegerv"));
  constexpr unsigned kFramebuffer = 0x8D40, kDrawBinding = 0x8CA6, kReadBinding = 0x8CAA;
  bind(kFramebuffer, 0);
  ASSERT_TRUE(ctx->makeCurrent().isOk());
  int draw = -1, read = -1;
  get(kDrawBinding, &draw);
  get(kReadBinding, &read);
  EXPECT_EQ(uint32_t(draw), ctx->framebuffer());
  EXPECT_EQ(uint32_t(read), ctx->framebuffer());
  EXPECT_NE(ctx->framebuffer(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Backends, ContextTest, test::allBackends(), test::backendTestName);

TEST(Headless, ErrorsForBadInput) {
  std::unique_ptr<HeadlessContext> ctx;
  HeadlessDesc d;
  d.width = 20000;
  EXPECT_EQ(HeadlessContext::create(d, &ctx).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(HeadlessContext::create({}, nullptr).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(ctx, nullptr);
  const std::vector<uint8_t> small(8);
  EXPECT_EQ(writePng("x.png", 4, 4, small).code(), StatusCode::kCountMismatch);
  uint32_t w, h;
  std::vector<uint8_t> px;
  EXPECT_EQ(readPng("/nonexistent/none.png", &w, &h, &px).code(), StatusCode::kIo);
}

TEST(GlContext, LoadRejectsNullAndNamesErrors) {
  GlInfo info;
  EXPECT_EQ(loadGl(nullptr, nullptr, &info).code(), StatusCode::kInvalidArgument);
  EXPECT_STREQ(glErrorName(0x0502), "GL_INVALID_OPERATION");
  EXPECT_STREQ(glErrorName(0x1234), "GL_UNKNOWN_ERROR");
}

}  // namespace
}  // namespace si
