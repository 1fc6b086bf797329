// The guest contract checked the way an engine meets it: with the engine's state set
// (host_state.h) and its own KHR_debug callback installed, every public call of si::gl that
// touches the context runs once, and after each the engine's state must be what it was and its
// callback must still receive the engine's own messages.
#pragma once

#include <string>
#include <vector>

namespace host {

struct GuestReport {
  std::vector<std::string> failures;  ///< Empty when every call behaved.
  int calls = 0;                      ///< Calls checked.
  size_t values = 0;                  ///< Values of the engine's state compared after each.
};

/// Runs the check on the current context (GL 4.5, si::loadGl not yet needed: it is called here
/// with `get_proc`/`user`). `width` x `height` is the engine's framebuffer size.
GuestReport checkEveryCall(void* (*get_proc)(void* user, const char* name), void* user,
                           unsigned width, unsigned height);

}  // namespace host
