// The x86 device's framebuffer hash of each .tpcmd stream given, one "HASH  FILE" line each, as
// `tinyphong replay --hash` prints them: the reference the target tests hold the images to
// (host_hashes.sh). A tool of its own, linked with the firmware built -O2 in every build type and
// without the image library, whose loading was most of a fixture's time (docs/TARGET.md, "The
// Cortex-M images").
#include <cstddef>
#include <cstdint>
#include <exception>
#include <iostream>
#include <span>
#include <string>
#include <vector>

#include "firmware/device.hpp"
#include "host/command_stream.hpp"

namespace {

std::string hash_of_stream(const std::string& path) {
  const std::vector<std::uint32_t> words = tp::host::read_command_file(path);
  std::vector<std::byte> memory(tp::host::memory_for_stream(words));
  tp::fw::Device device{std::span<std::byte>(memory)};
  tp::host::run_stream(device, words);
  if (!device.state().viewport_set) throw std::runtime_error("the stream sets no viewport");
  return tp::host::hash_hex(tp::host::framebuffer_hash(device.framebuffer()));
}

}  // namespace

int main(int argc, char** argv) {
  int status = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string path = argv[i];
    try {
      std::cout << hash_of_stream(path) << "  " << path << "\n";
    } catch (const std::exception& e) {
      std::cerr << "tp_host_hash: " << path << ": " << e.what() << "\n";
      status = 1;
    }
  }
  return status;
}
