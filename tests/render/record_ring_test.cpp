// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The instance record ring never hands out a region the GPU may still read: a wait that times
// out or fails is a named error, nothing is written, and the fence stays for the next try.
#include <glad/gl.h>

#include "gl/resources/record_ring.h"
#include "render/render_fixture.h"

namespace si {
namespace {

using namespace test;

GLenum GLAD_API_PTR timesOut(GLsync, GLbitfield, GLuint64) { return GL_TIMEOUT_EXPIRED; }
GLenum GLAD_API_PTR waitFails(GLsync, GLbitfield, GLuint64) { return GL_WAIT_FAILED; }

class RecordRingTest : public RenderTest {};

TEST_P(RecordRingTest, ARegionTheGpuMayStillReadIsNeverHandedOut) {
  detail::RecordRing ring;
  ring.configure(16384, 256, 1);  // One region: every acquire waits for the last frame's fence.
  ASSERT_TRUE(ring.reserve(1024).isOk());
  size_t base = 99;
  ASSERT_TRUE(ring.acquire(&base).isOk());
  EXPECT_EQ(base, 0u);
  ring.finishFrame();  // The region is fenced.
  for (detail::ClientWaitSync wait : {&timesOut, &waitFails}) {
    ring.setClientWait(wait);
    base = 77;
    const Status s = ring.acquire(&base);
    EXPECT_EQ(s.code(), StatusCode::kBackend);
    EXPECT_NE(s.message().find("record ring"), std::string::npos) << s.message();
    EXPECT_EQ(base, 77u);  // No region handed out.
  }
  // The fence stayed: the real wait passes it, and the region is handed out.
  ring.setClientWait(nullptr);
  ASSERT_TRUE(ring.acquire(&base).isOk());
  EXPECT_EQ(base, 0u);
  ring.release();
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

INSTANTIATE_TEST_SUITE_P(Backends, RecordRingTest, allBackends(), backendTestName);

}  // namespace
}  // namespace si
