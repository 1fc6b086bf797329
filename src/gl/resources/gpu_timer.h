// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once
// GPU time of a draw function (RendererDesc::measure_gpu_time): two timestamp queries.

#include <glad/gl.h>

#include <chrono>

#include "gl/programs/program_set.h"

namespace si::detail {

/// Milliseconds since `t0` (the draw functions' CPU time).
inline double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

/// While it lives, no buffer is bound to GL_QUERY_BUFFER, so query results read into memory (a
/// host's query buffer would turn the result pointers into offsets); the host's is bound again
/// at its end. Safe outside the state guard.
class QueryResultsToMemory {
 public:
  QueryResultsToMemory() {
    glGetIntegerv(GL_QUERY_BUFFER_BINDING, &host_);
    if (host_ != 0) glBindBuffer(GL_QUERY_BUFFER, 0);
  }
  ~QueryResultsToMemory() {
    if (host_ != 0) glBindBuffer(GL_QUERY_BUFFER, GLuint(host_));
  }
  QueryResultsToMemory(const QueryResultsToMemory&) = delete;
  QueryResultsToMemory& operator=(const QueryResultsToMemory&) = delete;

 private:
  GLint host_ = 0;
};

class GpuTimer {
 public:
  void create() { glCreateQueries(GL_TIMESTAMP, 2, queries_); }
  void release() {
    if (queries_[0] != kNoObject) glDeleteQueries(2, queries_);
    queries_[0] = queries_[1] = kNoObject;
  }
  /// Starts timing when `enabled`. Timestamps (glQueryCounter), not a GL_TIME_ELAPSED query:
  /// the host may have its own elapsed-time query active around the call.
  void begin(bool enabled) {
    active_ = enabled;
    if (active_) glQueryCounter(queries_[0], GL_TIMESTAMP);
  }
  /// Ends what begin() started (its second timestamp).
  void stop() {
    if (active_) glQueryCounter(queries_[1], GL_TIMESTAMP);
  }
  /// The GPU milliseconds between begin() and stop() (blocking), or -1 when it did not start.
  /// Safe outside the state guard (QueryResultsToMemory).
  double read() {
    if (!active_) return -1.0;
    active_ = false;
    const QueryResultsToMemory to_memory;
    GLuint64 start = 0, stop = 0;
    glGetQueryObjectui64v(queries_[0], GL_QUERY_RESULT, &start);
    glGetQueryObjectui64v(queries_[1], GL_QUERY_RESULT, &stop);
    return stop > start ? double(stop - start) * 1e-6 : 0.0;
  }
  /// stop() and read().
  double end() {
    stop();
    return read();
  }

 private:
  GLuint queries_[2] = {kNoObject, kNoObject};
  bool active_ = false;
};

}  // namespace si::detail
