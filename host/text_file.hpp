// Reading a whole input file with a size limit, for the scene and OBJ readers: a file over the
// limit is refused before it is held in memory, whatever size the file system reports (files
// under /proc report 0 and can be far larger).
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace tp::host {

enum class ReadResult { ok, cannot_open, too_large };

// Reads `file` into `text`; too_large (and `text` unspecified) when it holds more than
// max_bytes bytes. Reads in blocks, so that at most max_bytes + one block is ever held.
inline ReadResult read_text_file(const std::filesystem::path& file, std::uintmax_t max_bytes,
                                 std::string& text) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return ReadResult::cannot_open;
  text.clear();
  char block[1 << 16];
  while (in.read(block, sizeof block) || in.gcount() > 0) {
    text.append(block, static_cast<std::size_t>(in.gcount()));
    if (text.size() > max_bytes) return ReadResult::too_large;
  }
  return in.bad() ? ReadResult::cannot_open : ReadResult::ok;
}

}  // namespace tp::host
