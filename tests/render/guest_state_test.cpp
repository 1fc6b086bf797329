// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
// The guest contract on the EGL back-ends (a GPU's through EGL device), under the sanitizers and
// with the debug checks on: the consumer project's engine (tests/consumer/project/host_state.h,
// guest_calls.h) sets its own state and debug callback, runs every public call of si::gl that
// touches the context, and every piece of its state must be unchanged after each. The consumer test runs the
// same check in an outside project with its own glad loader linked beside the library.
#include <cstdio>

#include "guest_calls.h"
#include "render/render_fixture.h"

namespace si {
namespace {

using namespace test;

class GuestStateTest : public RenderTest {};

TEST_P(GuestStateTest, EveryCallLeavesTheEnginesStateAndDebugCallbackAsItFoundThem) {
  const host::GuestReport report =
      host::checkEveryCall(&HeadlessContext::getProcAddress, context_.get(), kSize, kSize);
  for (const std::string& f : report.failures) ADD_FAILURE() << f;
  std::printf("[ guest    ] %d calls, %zu values of the engine's state compared after each\n",
              report.calls, report.values);
  EXPECT_GE(report.calls, 48);
}

// EGL only: OSMesa keeps its state in the same Mesa core as EGL surfaceless (llvmpipe), so it
// would check nothing more for 20 s of the test run; the EGL device variant runs on a GPU.
INSTANTIATE_TEST_SUITE_P(Backends, GuestStateTest,
                         ::testing::Values(HeadlessBackend::kEglSurfaceless,
                                           HeadlessBackend::kEglDevice),
                         backendTestName);

}  // namespace
}  // namespace si
