// Writing a whole output file, for every file the tools write (command streams, images, the stress
// suite's JSON and bounds): the file holds all the bytes or is as it was. A write that fails
// part-way (a full disk, the file size limit) throws naming the file and leaves the old file, not
// a file cut short; the writers of text_file.hpp's readers.
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>

namespace tp::host {

namespace detail {
// All the bytes to an open descriptor; false if any write fails.
inline bool write_all(int fd, std::span<const std::byte> bytes) {
  const auto* data = reinterpret_cast<const char*>(bytes.data());
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(fd, data + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}
}  // namespace detail

// Writes `bytes` as the file `path`, or throws std::runtime_error "PATH: cannot write" (what) and
// leaves what was there. A new or regular file is written beside it, as PATH.part, and renamed over
// it. Anything else (a symbolic link, /dev/stdout, a pipe) is written through, as it is: the file
// a link names stays that file, and a device or pipe has no old contents to keep.
inline void replace_file(const std::string& path, std::span<const std::byte> bytes) {
  std::error_code e;
  const auto kind = std::filesystem::symlink_status(path, e).type();
  const bool replace =
      kind == std::filesystem::file_type::not_found || kind == std::filesystem::file_type::regular;
  const std::string file = replace ? path + ".part" : path;  // the one opened and written
  // O_EXCL | O_NOFOLLOW: PATH.part is this call's own file, never one that was there (a stale
  // one, or a link that would send the bytes elsewhere), so removing it on failure is safe.
  const int fd = replace ? ::open(file.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW, 0666)
                         : ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
  if (fd < 0) {
    const bool stale = replace && errno == EEXIST;
    throw std::runtime_error(
        path + ": cannot write" +
        (stale ? " (" + file + " exists: left by an interrupted write?)" : ""));
  }
  const bool written = detail::write_all(fd, bytes);
  const bool closed = ::close(fd) == 0;
  if (written && closed && (!replace || std::rename(file.c_str(), path.c_str()) == 0)) return;
  if (replace) std::filesystem::remove(file, e);
  throw std::runtime_error(path + ": cannot write");
}

inline void replace_file(const std::string& path, std::string_view text) {
  replace_file(path, std::as_bytes(std::span(text.data(), text.size())));
}

}  // namespace tp::host
