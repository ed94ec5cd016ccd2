#include "link/child_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <stdexcept>
#include <thread>

namespace hil {

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const std::string& stderr_path,
                           const std::vector<std::string>& env) {
  int in_pipe[2];
  int out_pipe[2];
  if (pipe(in_pipe) != 0 || pipe(out_pipe) != 0) {
    throw std::runtime_error("pipe() failed");
  }
  // A peer that dies mid-write must not kill the simulator.
  signal(SIGPIPE, SIG_IGN);
  std::vector<char*> args;
  for (const auto& a : argv) {
    args.push_back(const_cast<char*>(a.c_str()));
  }
  args.push_back(nullptr);
  pid_ = fork();
  if (pid_ < 0) {
    throw std::runtime_error("fork() failed");
  }
  if (pid_ == 0) {
    for (const std::string& e : env) {
      const auto eq = e.find('=');
      if (eq != std::string::npos) {
        setenv(e.substr(0, eq).c_str(), e.substr(eq + 1).c_str(), 1);
      }
    }
    dup2(in_pipe[0], STDIN_FILENO);
    dup2(out_pipe[1], STDOUT_FILENO);
    if (!stderr_path.empty()) {
      const int fd = open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd >= 0) {
        dup2(fd, STDERR_FILENO);
        close(fd);
      }
    }
    close(in_pipe[0]);
    close(in_pipe[1]);
    close(out_pipe[0]);
    close(out_pipe[1]);
    execvp(args[0], args.data());
    _exit(127);
  }
  close(in_pipe[0]);
  close(out_pipe[1]);
  to_child_ = in_pipe[1];
  from_child_ = out_pipe[0];
  fcntl(from_child_, F_SETFL, fcntl(from_child_, F_GETFL) | O_NONBLOCK);
}

ChildProcess::~ChildProcess() { stop(); }

bool ChildProcess::write_all(std::span<const std::uint8_t> bytes) {
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = write(to_child_, bytes.data() + sent, bytes.size() - sent);
    if (n < 0) {
      if (errno == EINTR) {
        continue;
      }
      return false;
    }
    sent += static_cast<std::size_t>(n);
  }
  return true;
}

std::size_t ChildProcess::read_some(std::span<std::uint8_t> buffer,
                                    std::chrono::milliseconds timeout) {
  pollfd pfd{from_child_, POLLIN, 0};
  const int ready = poll(&pfd, 1, static_cast<int>(timeout.count()));
  if (ready <= 0) {
    return 0;
  }
  const ssize_t n = read(from_child_, buffer.data(), buffer.size());
  return n > 0 ? static_cast<std::size_t>(n) : 0;
}

std::size_t ChildProcess::set_output_pipe_size(std::size_t bytes) {
  fcntl(from_child_, F_SETPIPE_SZ, static_cast<int>(bytes));
  const int size = fcntl(from_child_, F_GETPIPE_SZ);
  return size > 0 ? static_cast<std::size_t>(size) : 0;
}

bool ChildProcess::running() {
  if (pid_ <= 0) {
    return false;
  }
  int status = 0;
  if (waitpid(pid_, &status, WNOHANG) == pid_) {
    pid_ = -1;
    return false;
  }
  return true;
}

void ChildProcess::stop() {
  if (to_child_ >= 0) {
    close(to_child_);
    to_child_ = -1;
  }
  if (pid_ > 0) {
    kill(pid_, SIGTERM);
    for (int i = 0; i < 100 && running(); ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (pid_ > 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
      pid_ = -1;
    }
  }
  if (from_child_ >= 0) {
    close(from_child_);
    from_child_ = -1;
  }
}

std::vector<std::string> qemu_command(const std::string& elf, const std::string& log_path,
                                      const std::string& key_slot_path) {
  // UART0 carries the link on stdio; UART1 (the firmware's log) goes to a file or nowhere.
  //
  // The stdio back end reaches UART0 through a multiplexer (mux=on) for speed:
  // the CMSDK UART model takes one byte at a time, and without the mux each
  // byte costs a round trip between QEMU's I/O thread and the vCPU thread (the
  // I/O thread reads the next byte only after the guest took the previous one;
  // about 30-50 us per byte). The mux keeps reading ahead into its 32-byte
  // buffer and hands the next byte over synchronously when the guest reads
  // the UART's DATA register, about 3x faster (docs/port.md).
  // -echr 256 turns off the mux's escape character (Ctrl-A by default, which
  // would swallow link bytes and quit QEMU on 0x01 'x'): no byte equals 256.
  // Bytes that arrive before the firmware enables the UART wait in the mux
  // until the next byte comes in; LinkClient sends a lone delimiter when a
  // reply is late (ClientPacing::nudge_after).
  std::vector<std::string> cmd = {"qemu-system-arm", "-M", "mps2-an500", "-nographic", "-monitor", "none",
                                  "-icount", "shift=0", "-echr", "256",
                                  "-chardev", "stdio,id=link,mux=on", "-serial", "chardev:link",
                                  "-serial", log_path.empty() ? std::string("null") : "file:" + log_path,
                                  "-kernel", elf};
  if (!key_slot_path.empty()) {
    // The key slot of port/mps2_an500 (kKeySlotAddress), filled before the core starts.
    cmd.insert(cmd.end(), {"-device", "loader,file=" + key_slot_path + ",addr=0x203FFF00,force-raw=on"});
  }
  return cmd;
}

std::vector<std::string> host_firmware_command(const std::string& executable) {
  return {executable};
}

}  // namespace hil
