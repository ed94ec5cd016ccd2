#include "link/firmware_process.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <vector>

namespace hil {
namespace {

void write_private(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) {
    throw std::runtime_error("cannot write " + path);
  }
  out.close();
  chmod(path.c_str(), 0600);
}

}  // namespace

template <class Bytes>
Bytes random_bytes() {
  Bytes bytes{};
  std::random_device rd;
  for (auto& b : bytes) {
    b = static_cast<std::uint8_t>(rd());
  }
  return bytes;
}

LinkKey random_link_key() { return random_bytes<LinkKey>(); }

std::optional<LinkKey> read_link_key(const std::string& path, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    error = "cannot read key file '" + path + "'";
    return std::nullopt;
  }
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  LinkKey key{};
  if (bytes.size() == key.size()) {
    std::copy(bytes.begin(), bytes.end(), key.begin());
    return key;
  }
  std::string hex;
  for (const char c : bytes) {
    if (std::isspace(static_cast<unsigned char>(c)) == 0) {
      hex += c;
    }
  }
  if (hex.size() != 2 * key.size() ||
      hex.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos) {
    error = "key file '" + path + "' holds neither 16 bytes nor 32 hexadecimal digits (an AES-128 key)";
    return std::nullopt;
  }
  for (std::size_t i = 0; i < key.size(); ++i) {
    key[i] = static_cast<std::uint8_t>(std::stoul(hex.substr(2 * i, 2), nullptr, 16));
  }
  return key;
}

LinkKey link_key_from(const std::string& path) {
  if (path.empty()) {
    return random_link_key();
  }
  std::string error;
  const auto key = read_link_key(path, error);
  if (!key) {
    throw std::runtime_error(error);
  }
  return *key;
}

FirmwareProcess::FirmwareProcess(const std::string& target, const std::string& firmware, const LinkKey& key,
                                 const std::string& log) {
  std::string tmpl = (std::filesystem::temp_directory_path() / "itplan-link-XXXXXX").string();
  if (mkdtemp(tmpl.data()) == nullptr) {
    throw std::runtime_error("cannot create a private directory for the link key");
  }
  dir_ = tmpl;
  try {
    const std::string key_file = dir_ + "/key.bin";
    write_private(key_file, std::vector<std::uint8_t>(key.begin(), key.end()));
    if (target == "qemu") {
      // port/mps2_an500's key slot: "ITPK", the key, this boot's entropy.
      std::vector<std::uint8_t> slot{'I', 'T', 'P', 'K'};
      slot.insert(slot.end(), key.begin(), key.end());
      const BootEntropy entropy = random_bytes<BootEntropy>();
      slot.insert(slot.end(), entropy.begin(), entropy.end());
      const std::string slot_file = dir_ + "/key_slot.bin";
      write_private(slot_file, slot);
      child_ = std::make_unique<ChildProcess>(qemu_command(firmware, log, slot_file), "");
    } else if (target == "host") {
      child_ = std::make_unique<ChildProcess>(host_firmware_command(firmware), log,
                                              std::vector<std::string>{"ITP_LINK_KEY_FILE=" + key_file});
    } else {
      throw std::runtime_error("unknown target '" + target + "'");
    }
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
    throw;
  }
}

FirmwareProcess::~FirmwareProcess() {
  child_.reset();  // ends the process before its key files go
  std::error_code ec;
  std::filesystem::remove_all(dir_, ec);
}

}  // namespace hil
