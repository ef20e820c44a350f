#pragma once
// Preconditions checked in every build. assert() is compiled out wherever NDEBUG is defined —
// the Release build and the sanitizer build both define it — so a caller's bug ran on silently
// into out-of-bounds reads. A violated ODONATA_EXPECTS is a bug in the caller: the process stops
// at once, naming the file, the line and the condition. Bad input is never a precondition: it is
// validated and reported where it enters.

#include <cstdio>
#include <cstdlib>

namespace odonata::contract {

[[noreturn]] inline void PreconditionFailed(const char* condition, const char* file, int line) {
  std::fprintf(stderr, "%s:%d: precondition failed: %s\n", file, line, condition);
  std::abort();
}

}  // namespace odonata::contract

#define ODONATA_EXPECTS(condition)    \
  ((condition) ? static_cast<void>(0) \
               : ::odonata::contract::PreconditionFailed(#condition, __FILE__, __LINE__))
