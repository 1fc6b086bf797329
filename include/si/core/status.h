// SkinnedInstancing — SPDX-License-Identifier: MIT (see LICENSE)
#pragma once

/// \file
/// The small status value every public entry point returns. No exception leaves the library:
/// a function that can fail returns a `Status` (or fills an output and returns one), and on
/// failure its outputs are left untouched or empty.

#include <cstdint>
#include <string>
#include <utility>

namespace si {

/// What went wrong, as a code tests can assert on. The message says where and why.
enum class StatusCode : uint8_t {
  kOk = 0,           ///< Success.
  kInvalidArgument,  ///< A desc or job field, or a caller span, breaks a documented rule.
  kNotFinite,        ///< A value that must be finite is NaN or infinite.
  kOutOfRange,       ///< An index or value lies outside its allowed range.
  kNotSorted,        ///< Values that must be strictly increasing (key times, parents) are not.
  kCountMismatch,    ///< Two arrays that must have matching element counts do not.
  kUnsupported,      ///< Valid input that this format or back-end cannot represent.
  kLimitExceeded,    ///< The input needs more than a hard or queried limit allows.
  kCorrupt,          ///< Bytes of a file or buffer are malformed, truncated or inconsistent.
  kIo,               ///< A file could not be opened, read or written.
  kNotFound,         ///< A named or indexed element does not exist.
  kAmbiguous,        ///< A choice is needed (several candidates) and none was given.
  kBackend,          ///< The graphics back-end or context reported an error.
  kToleranceNotMet,  ///< An approximation could not meet the error tolerance asked for.
};

/// Returns the enumerator's name without the `k`, e.g. "InvalidArgument".
const char* statusCodeName(StatusCode code);

/// A status code plus a message naming the field and the rule that failed, for example
/// "clip 'run': joint 12 rotation: key times not increasing at key 3".
class [[nodiscard]] Status {
 public:
  /// A successful status.
  Status() = default;
  /// A status with `code` and `message`; `code` may be kOk (the message is then ignored).
  Status(StatusCode code, std::string message)
      : code_(code), message_(code == StatusCode::kOk ? std::string() : std::move(message)) {}

  /// Returns a successful status.
  static Status ok() { return Status(); }

  /// True when the operation succeeded.
  bool isOk() const { return code_ == StatusCode::kOk; }
  /// The failure code, kOk on success.
  StatusCode code() const { return code_; }
  /// The failure message, empty on success.
  const std::string& message() const { return message_; }
  /// "Code: message", or "Ok".
  std::string toString() const;

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

}  // namespace si
