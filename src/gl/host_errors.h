// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// GL errors the host left pending when a library call starts are not the library's to report as
// its failure, nor its to drop: they are taken (glGetError cannot leave them for the host),
// logged as warnings naming the call, and kept for the host (si::takeHostGlErrors), so the
// call's own error check blames only what it did.

namespace si::detail {

/// Drains glGetError() (at most 16 errors: a lost context can report errors forever), logs
/// each pending error at LogLevel::kWarning as the host's, before the call named `what`, and
/// keeps it for takeHostGlErrors() on this thread.
void takeHostErrors(const char* what);

}  // namespace si::detail
