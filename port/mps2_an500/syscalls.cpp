// The few C library hooks a bare-metal newlib link can reach. There is no
// heap: _sbrk refuses every request, so a stray malloc fails instead of
// quietly carving memory (and the size report shows none is linked).
#include <cerrno>
#include <cstddef>

extern "C" {

void* _sbrk(std::ptrdiff_t) {
  errno = ENOMEM;
  return reinterpret_cast<void*>(-1);
}

[[noreturn]] void _exit(int) {
  for (;;) {
  }
}

}  // extern "C"
