#pragma once
// A child process whose stdin/stdout are the serial line: the host-port
// firmware, or qemu-system-arm with the firmware's UART0 on -serial stdio.
#include <string>
#include <vector>

#include "link/byte_transport.hpp"

namespace hil {

class ChildProcess final : public ByteTransport {
 public:
  // argv[0] is looked up in PATH. `stderr_path` receives the child's stderr
  // ("" keeps the parent's); `env` holds NAME=VALUE entries added to the
  // child's environment. Throws std::runtime_error if it cannot start.
  ChildProcess(const std::vector<std::string>& argv, const std::string& stderr_path,
               const std::vector<std::string>& env = {});
  ~ChildProcess() override;
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  bool write_all(std::span<const std::uint8_t> bytes) override;
  std::size_t read_some(std::span<std::uint8_t> buffer,
                        std::chrono::milliseconds timeout) override;

  bool running();
  // Shrinks (or grows) the pipe the child writes into; returns its capacity
  // in bytes afterwards (Linux F_SETPIPE_SZ), 0 if that failed.
  std::size_t set_output_pipe_size(std::size_t bytes);
  // Ends the child (SIGTERM, then SIGKILL) and reaps it.
  void stop();

 private:
  int pid_ = -1;
  int to_child_ = -1;    // child's stdin
  int from_child_ = -1;  // child's stdout
};

// Command lines for the two process targets. `key_slot_path` (may be ""):
// a file QEMU's generic loader writes into the firmware's key slot
// (docs/port.md, "Key provisioning").
std::vector<std::string> qemu_command(const std::string& elf, const std::string& log_path,
                                      const std::string& key_slot_path = "");
std::vector<std::string> host_firmware_command(const std::string& executable);

}  // namespace hil
