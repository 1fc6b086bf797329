// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// GPU time of a draw function (RendererDesc::measure_gpu_time): one GL_TIME_ELAPSED query.

#include <glad/gl.h>

#include <chrono>

#include "gl/programs/program_set.h"

namespace si::detail {

/// Milliseconds since `t0` (the draw functions' CPU time).
inline double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

class GpuTimer {
 public:
  void create() { glCreateQueries(GL_TIME_ELAPSED, 1, &query_); }
  void release() {
    if (query_ != kNoObject) glDeleteQueries(1, &query_);
    query_ = kNoObject;
  }
  /// Starts timing when `enabled`.
  void begin(bool enabled) {
    active_ = enabled;
    if (active_) glBeginQuery(GL_TIME_ELAPSED, query_);
  }
  /// Ends what begin() started and returns the GPU milliseconds (blocking), or -1 when it did
  /// not start.
  double end() {
    if (!active_) return -1.0;
    active_ = false;
    glEndQuery(GL_TIME_ELAPSED);
    GLuint64 ns = 0;
    glGetQueryObjectui64v(query_, GL_QUERY_RESULT, &ns);
    return double(ns) * 1e-6;
  }

 private:
  GLuint query_ = kNoObject;
  bool active_ = false;
};

}  // namespace si::detail
