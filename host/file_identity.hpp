// Whether an output would overwrite an input. By the file itself, not its name: a link, `./x`,
// `dir/../x` or a hard link name the same file as `x` (on a case-insensitive file system `X`
// does too). The commands that write files check their outputs against their inputs before
// anything is written, so that a slip such as `record scene.json -o scene.json` loses nothing.
#pragma once

#include <filesystem>
#include <system_error>

namespace tp::host {

// True when both exist and are one file (the same device and inode). A file not written yet is
// no input, and a path that cannot be examined is not known to be one.
inline bool same_file(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::error_code e;
  const bool same = std::filesystem::equivalent(a, b, e);
  return same && !e;
}

}  // namespace tp::host
