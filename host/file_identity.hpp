// Whether an output would overwrite an input. By the file itself, not its name: a link, `./x`,
// `dir/../x` or a hard link name the same file as `x` (on a case-insensitive file system `X`
// does too). The commands that write files check their outputs against their inputs before
// anything is written, so that a slip such as `record scene.json -o scene.json` loses nothing.
#pragma once

#include <filesystem>
#include <iostream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

namespace tp::host {

// True when both exist and are one file (the same device and inode). A file not written yet is
// no input, and a path that cannot be examined is not known to be one.
inline bool same_file(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::error_code e;
  const bool same = std::filesystem::equivalent(a, b, e);
  return same && !e;
}

// Whether two outputs would be one file: the same file where both exist, else the same path made
// absolute and normal, links of its existing folders followed (`./x`, `dir/../x` and `x`).
inline bool same_output(const std::filesystem::path& a, const std::filesystem::path& b) {
  if (same_file(a, b)) return true;
  std::error_code e;
  const auto full = [&](const std::filesystem::path& p) {
    return std::filesystem::weakly_canonical(std::filesystem::absolute(p, e), e);
  };
  const std::filesystem::path fa = full(a), fb = full(b);
  return !e && fa == fb;
}

// Whether writing `path` writes into what this process's standard output is, a pipe or a file
// (`-o /dev/stdout | ...`, or `-o f > f`); a character device (a terminal, /dev/null) is not
// counted, since nothing written there is a file to keep apart. By device and inode:
// std::filesystem::equivalent refuses pipes ("operation not supported").
inline bool is_standard_output(const std::filesystem::path& path) {
  struct stat out {};
  struct stat file {};
  return !path.empty() && ::fstat(STDOUT_FILENO, &out) == 0 && !S_ISCHR(out.st_mode) &&
         ::stat(path.c_str(), &file) == 0 && out.st_dev == file.st_dev && out.st_ino == file.st_ino;
}

// A file a command reads, and how a refusal names it.
struct Input {
  std::filesystem::path path;
  std::string what;  // "the scene file scenes/teapot.json"
};

// An output that is one of the inputs, by any name, is refused before anything is written: true
// after the message on stderr, for exit status 2. Empty outputs (options not given) are skipped.
inline bool writes_over_input(std::string_view command, const std::vector<std::string>& outputs,
                              const std::vector<Input>& inputs) {
  for (const std::string& out : outputs)
    for (const Input& in : inputs)
      if (!out.empty() && same_file(out, in.path)) {
        std::cerr << "tinyphong " << command << ": " << out << " is " << in.what
                  << ": nothing written\n";
        return true;
      }
  return false;
}

}  // namespace tp::host
