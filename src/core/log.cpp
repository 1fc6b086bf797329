// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "si/core/log.h"

#include <mutex>

namespace si {
namespace {
std::mutex g_mutex;
LogCallback g_callback = nullptr;
void* g_user_data = nullptr;
}  // namespace

void setLogCallback(LogCallback callback, void* user_data) {
  std::lock_guard<std::mutex> lock(g_mutex);
  g_callback = callback;
  g_user_data = user_data;
}

void logMessage(LogLevel level, const std::string& message) {
  LogCallback callback;
  void* user_data;
  {
    // Copied under the lock, called outside it, so a callback may log or reinstall itself.
    std::lock_guard<std::mutex> lock(g_mutex);
    callback = g_callback;
    user_data = g_user_data;
  }
  if (callback != nullptr)
    callback(level == LogLevel::kDefault ? LogLevel::kInfo : level, message.c_str(), user_data);
}

const char* logLevelName(LogLevel level) {
  switch (level) {
    case LogLevel::kDebug: return "debug";
    case LogLevel::kDefault:
    case LogLevel::kInfo: return "info";
    case LogLevel::kWarning: return "warning";
    case LogLevel::kError: return "error";
  }
  return "info";
}

}  // namespace si
