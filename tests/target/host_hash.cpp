// The x86 device's framebuffer hash of each .tpcmd stream given, one "HASH  FILE" line each, as
// `tinyphong replay --hash` prints them: the reference the target tests hold the images to
// (host_hashes.sh). A tool of its own, linked with the firmware built -O2 in every build type and
// without the image library, whose loading was most of a fixture's time (docs/TARGET.md, "The
// Cortex-M images").
#include <exception>
#include <iostream>
#include <string>

#include "host/command_stream.hpp"

namespace {

std::string hash_of_stream(const std::string& path) {
  const tp::host::StreamReplay replay(tp::host::read_command_file(path));
  return tp::host::hash_hex(tp::host::framebuffer_hash(replay.device().framebuffer()));
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
