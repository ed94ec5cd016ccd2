#include "itp/core/assert.hpp"

namespace itp {
namespace {
PreconditionHook g_hook = nullptr;  // installed once at start-up, before planning
}

void set_precondition_hook(PreconditionHook hook) { g_hook = hook; }

void precondition_failed(const char* expression, const char* file, int line) {
  if (g_hook != nullptr) {
    g_hook(expression, file, line);
  }
  __builtin_trap();
}

}  // namespace itp
