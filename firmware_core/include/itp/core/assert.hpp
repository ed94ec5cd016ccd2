#pragma once
// One hook for broken preconditions (programming errors, not bad input: bad
// input is reported through status values). The default hook traps; hosts
// and tests may install their own.

namespace itp {

using PreconditionHook = void (*)(const char* expression, const char* file, int line);

void set_precondition_hook(PreconditionHook hook);
[[noreturn]] void precondition_failed(const char* expression, const char* file, int line);

}  // namespace itp

#define ITP_EXPECTS(cond) \
  ((cond) ? static_cast<void>(0) : ::itp::precondition_failed(#cond, __FILE__, __LINE__))
