#pragma once
// Starting a firmware for the simulator: the host-port firmware or QEMU with
// the Cortex-M7 ELF, provisioned with a link key (docs/port.md, "Key
// provisioning"). The key is given (--key FILE) or made fresh for the run;
// the files the firmware reads it from live in a private temporary directory
// (0700) that is removed when the process ends.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "link/child_process.hpp"

namespace hil {

// The link's long-term key: AES-128 (the link's MAC is AES-128-CMAC).
using LinkKey = std::array<std::uint8_t, 16>;
// Boot entropy handed to a QEMU firmware through its key slot.
using BootEntropy = std::array<std::uint8_t, 32>;

// A fresh random key (std::random_device).
LinkKey random_link_key();
// Reads a key file: 16 raw bytes, or 32 hexadecimal digits (whitespace
// around them ignored). nullopt, with `error` set, otherwise.
std::optional<LinkKey> read_link_key(const std::string& path, std::string& error);
// `path` empty: a random key; else the file's key (throws std::runtime_error
// naming the problem when it cannot be read).
LinkKey link_key_from(const std::string& path);

class FirmwareProcess {
 public:
  // target "host" (an executable) or "qemu" (an ELF). `log`: the firmware's
  // log lines go to this file ("" keeps them out). Throws std::runtime_error.
  FirmwareProcess(const std::string& target, const std::string& firmware, const LinkKey& key,
                  const std::string& log = "");
  ~FirmwareProcess();
  FirmwareProcess(const FirmwareProcess&) = delete;
  FirmwareProcess& operator=(const FirmwareProcess&) = delete;

  ChildProcess& process() { return *child_; }

 private:
  std::string dir_;  // the private directory with key.bin and key_slot.bin
  std::unique_ptr<ChildProcess> child_;
};

}  // namespace hil
