// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// Diagnostics. The library never prints on its own: warnings (a skipped glTF channel, a
/// renormalized weight) and debug messages go to a callback the application installs.

#include <string>

namespace si {

/// Severity of a log message.
enum class LogLevel : unsigned char {
  kDefault = 0,  ///< Not a real level; treated as kInfo.
  kDebug,
  kInfo,
  kWarning,
  kError,
};

/// Receives one message. `message` is only valid during the call. May be called from any thread
/// that calls into the library; the callback must be thread-safe if the application is threaded.
using LogCallback = void (*)(LogLevel level, const char* message, void* user_data);

/// Installs `callback` (nullptr silences the library, the default) with `user_data`.
void setLogCallback(LogCallback callback, void* user_data);

/// Sends `message` to the installed callback, if any. Used by every layer of the library.
void logMessage(LogLevel level, const std::string& message);

/// Returns "debug", "info", "warning" or "error".
const char* logLevelName(LogLevel level);

}  // namespace si
