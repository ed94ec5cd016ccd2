// Host port: the firmware as an ordinary process. The serial line is
// stdin/stdout (a simulator drives it through pipes), the log is stderr and
// the counter is CLOCK_MONOTONIC in nanoseconds. The key slot is a file named
// by the environment variable ITP_LINK_KEY_FILE (16 raw bytes, as hil_sim
// writes it for the firmware it starts), the boot entropy getrandom().
#include <fcntl.h>
#include <poll.h>
#include <sys/random.h>
#include <unistd.h>

#include <cstdlib>

#include <cerrno>
#include <cstring>
#include <ctime>

#include "port/port.hpp"

namespace port {
namespace {
bool g_open = true;
}

void init() {
  const int flags = fcntl(STDIN_FILENO, F_GETFL);
  fcntl(STDIN_FILENO, F_SETFL, flags | O_NONBLOCK);
}

std::uint64_t counter_ticks() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::uint64_t>(ts.tv_sec) * 1000000000u +
         static_cast<std::uint64_t>(ts.tv_nsec);
}

std::uint64_t counter_hz() { return 1000000000u; }

std::size_t serial_read(std::span<std::uint8_t> buffer) {
  const ssize_t n = read(STDIN_FILENO, buffer.data(), buffer.size());
  if (n > 0) {
    return static_cast<std::size_t>(n);
  }
  if (n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
    g_open = false;  // end of file or a broken pipe: the simulator is gone
  }
  return 0;
}

std::size_t serial_write(std::span<const std::uint8_t> bytes) {
  const ssize_t n = write(STDOUT_FILENO, bytes.data(), bytes.size());
  if (n > 0) {
    return static_cast<std::size_t>(n);
  }
  if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
    g_open = false;
  }
  return 0;
}

void log_line(const char* text) {
  const ssize_t ignored_a = write(STDERR_FILENO, text, std::strlen(text));
  const ssize_t ignored_b = write(STDERR_FILENO, "\n", 1);
  static_cast<void>(ignored_a);
  static_cast<void>(ignored_b);
}

void idle() {
  pollfd pfd{STDIN_FILENO, POLLIN, 0};
  poll(&pfd, 1, 1);  // wait at most 1 ms for input
}

std::uint32_t stack_size_bytes() { return 0u; }  // the host's stack is the OS's business
std::uint32_t stack_peak_bytes() { return 0u; }

bool keep_running() { return g_open; }

bool link_key(std::span<std::uint8_t, kLinkKeyBytes> key) {
  const char* path = std::getenv("ITP_LINK_KEY_FILE");
  if (path == nullptr || *path == '\0') {
    return false;
  }
  const int fd = open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    return false;
  }
  std::size_t got = 0;
  while (got < key.size()) {
    const ssize_t n = read(fd, key.data() + got, key.size() - got);
    if (n <= 0) {
      break;
    }
    got += static_cast<std::size_t>(n);
  }
  std::uint8_t extra = 0;
  const bool exact = got == key.size() && read(fd, &extra, 1) == 0;  // exactly 16 bytes
  close(fd);
  return exact;
}

bool boot_entropy(std::span<std::uint8_t, kBootEntropyBytes> entropy) {
  return getrandom(entropy.data(), entropy.size(), 0) == static_cast<ssize_t>(entropy.size());
}

}  // namespace port
