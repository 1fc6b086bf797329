// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// GL errors the host left pending when a library call starts are not the library's to report as
// its failure: they are drained (glGetError cannot leave them for the host) and logged as
// warnings naming the call, so the call's own error check blames only what it did.

namespace si::detail {

/// Drains glGetError() (at most 16 errors: a lost context can report errors forever) and logs
/// each pending error at LogLevel::kWarning as the host's, before the call named `what`.
void logHostErrors(const char* what);

}  // namespace si::detail
