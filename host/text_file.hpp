// Reading a whole input file with a size limit, for the scene and OBJ readers: a file over the
// limit is refused before it is held in memory, whatever size the file system reports (files
// under /proc report 0 and can be far larger).
#pragma once

#include <cerrno>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

namespace tp::host {

enum class ReadResult { ok, cannot_open, too_large };

// Reads `file` into `text`; too_large (and `text` unspecified) when it holds more than
// max_bytes bytes. Reads in blocks, so that at most max_bytes + one block is ever held. On
// cannot_open, *os_error (if given) is the system's reason (errno), for the message: "cannot open
// scene file" alone did not say whether the file was missing or unreadable.
inline ReadResult read_text_file(const std::filesystem::path& file, std::uintmax_t max_bytes,
                                 std::string& text, int* os_error = nullptr) {
  const auto failed = [os_error] {
    if (os_error != nullptr) *os_error = errno;
    return ReadResult::cannot_open;
  };
  errno = 0;
  std::ifstream in(file, std::ios::binary);
  if (!in) return failed();
  text.clear();
  char block[1 << 16];
  while (in.read(block, sizeof block) || in.gcount() > 0) {
    text.append(block, static_cast<std::size_t>(in.gcount()));
    if (text.size() > max_bytes) return ReadResult::too_large;
  }
  return in.bad() ? failed() : ReadResult::ok;
}

// The reason read_text_file gave, for a message: " (No such file or directory)", or nothing.
inline std::string os_reason(int os_error) {
  return os_error != 0 ? " (" + std::generic_category().message(os_error) + ")" : std::string();
}

}  // namespace tp::host
