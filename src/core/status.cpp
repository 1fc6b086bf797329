// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#include "si/core/status.h"

namespace si {

const char* statusCodeName(StatusCode code) {
  switch (code) {
    case StatusCode::kOk: return "Ok";
    case StatusCode::kInvalidArgument: return "InvalidArgument";
    case StatusCode::kNotFinite: return "NotFinite";
    case StatusCode::kOutOfRange: return "OutOfRange";
    case StatusCode::kNotSorted: return "NotSorted";
    case StatusCode::kCountMismatch: return "CountMismatch";
    case StatusCode::kUnsupported: return "Unsupported";
    case StatusCode::kLimitExceeded: return "LimitExceeded";
    case StatusCode::kCorrupt: return "Corrupt";
    case StatusCode::kIo: return "Io";
    case StatusCode::kNotFound: return "NotFound";
    case StatusCode::kAmbiguous: return "Ambiguous";
    case StatusCode::kBackend: return "Backend";
    case StatusCode::kToleranceNotMet: return "ToleranceNotMet";
  }
  return "Unknown";
}

std::string Status::toString() const {
  if (isOk()) return "Ok";
  return std::string(statusCodeName(code_)) + ": " + message_;
}

}  // namespace si
