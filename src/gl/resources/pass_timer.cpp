// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "gl/resources/pass_timer.h"

#include <algorithm>

#include "core/str_cat.h"

namespace si {

const char* gpuPassName(GpuPass pass) {
  switch (pass) {
    case GpuPass::kUpload:
      return "upload";
    case GpuPass::kCull:
      return "cull";
    case GpuPass::kCommands:
      return "commands";
    case GpuPass::kScatter:
      return "scatter";
    case GpuPass::kCompose:
      return "compose";
    case GpuPass::kSkin:
      return "skin";
    case GpuPass::kDraw:
      return "draw";
    case GpuPass::kImpostors:
      return "impostors";
    case GpuPass::kDepthPyramid:
      return "depth-pyramid";
    case GpuPass::kCount:
      break;
  }
  return "unknown";
}

namespace detail {

void PassTimer::release() {
  if (!queries_.empty()) glDeleteQueries(GLsizei(queries_.size()), queries_.data());
  queries_.clear();
  sets_.clear();
  active_ = nullptr;
}

uint64_t PassTimer::begin(uint32_t sets) {
  if (queries_.empty()) {
    queries_.assign(size_t(sets) * kStamps, 0);
    glCreateQueries(GL_TIMESTAMP, GLsizei(queries_.size()), queries_.data());
    sets_.assign(sets, Set());
  }
  const uint64_t ticket = ++issued_;
  const size_t index = size_t((ticket - 1) % sets_.size());
  active_ = &sets_[index];
  active_->ticket = ticket;
  active_->stamps = 1;
  glQueryCounter(queries_[index * kStamps], GL_TIMESTAMP);
  return ticket;
}

void PassTimer::stamp(GpuPass pass) {
  const size_t index = size_t(active_ - sets_.data());
  active_->passes[active_->stamps] = pass;
  glQueryCounter(queries_[index * kStamps + active_->stamps], GL_TIMESTAMP);
  ++active_->stamps;
}

void PassTimer::mark(GpuPass pass) {
  // The last stamp is end()'s.
  if (active_ != nullptr && active_->stamps + 1 < kStamps) stamp(pass);
}

void PassTimer::end(GpuPass rest) {
  if (active_ == nullptr) return;
  stamp(rest);
  active_ = nullptr;
}

Status PassTimer::read(uint64_t ticket, GpuPassTimes* out) const {
  if (ticket == 0 || ticket > issued_)
    return {StatusCode::kInvalidArgument,
            strCat("readGpuPasses: ticket ", ticket, " was never given (", issued_,
                   " given; DrawStats::gpu_pass_ticket, with RendererDesc::measure_gpu_passes)")};
  const size_t index = size_t((ticket - 1) % sets_.size());
  const Set& set = sets_[index];
  if (set.ticket != ticket)
    return {StatusCode::kNotFound,
            strCat("readGpuPasses: ticket ", ticket, " is older than the last ", sets_.size(),
                   " draws (their stamps were reused)")};
  *out = GpuPassTimes();
  if (&set == active_) return Status::ok();  // Read inside its own draw: not ready.
  const QueryResultsToMemory to_memory;
  const GLuint* q = &queries_[index * kStamps];
  bool ready = true;
  for (uint32_t i = set.stamps; i-- > 0 && ready;) {  // The last stamp is usually the last done.
    GLuint available = GL_FALSE;
    glGetQueryObjectuiv(q[i], GL_QUERY_RESULT_AVAILABLE, &available);
    ready = available == GL_TRUE;
  }
  if (ready) {
    GLuint64 previous = 0;
    glGetQueryObjectui64v(q[0], GL_QUERY_RESULT, &previous);
    const GLuint64 first = previous;
    for (uint32_t i = 1; i < set.stamps; ++i) {
      GLuint64 now = 0;
      glGetQueryObjectui64v(q[i], GL_QUERY_RESULT, &now);
      // Timestamps of one context increase; a driver's equal or wrapped one counts as nothing.
      if (now > previous) out->ms[size_t(set.passes[i])] += double(now - previous) * 1e-6;
      previous = std::max(previous, now);
    }
    out->total_ms = double(previous - first) * 1e-6;
    out->ready = true;
  }
  return Status::ok();
}

}  // namespace detail
}  // namespace si
