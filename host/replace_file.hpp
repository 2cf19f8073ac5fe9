// Writing a whole output file, for every file the tools write (command streams, images, the stress
// suite's JSON and bounds): the file holds all the new bytes or is as it was. A write that fails
// part-way (a full disk, the file size limit) throws naming the file and the cause and leaves the
// old file, not a file cut short.
#pragma once

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>

namespace tp::host {

namespace detail {

// All the bytes to an open descriptor; false (errno set) if any write fails.
inline bool write_all(int fd, std::span<const std::byte> bytes) {
  const auto* data = reinterpret_cast<const char*>(bytes.data());
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(fd, data + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return false;
    if (n == 0) {
      errno = EIO;
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  return true;
}

[[noreturn]] inline void cannot_write(const std::string& path, int error) {
  throw std::runtime_error(path + ": cannot write: " + std::strerror(error));
}

// The file a chain of symbolic links ends at (it may not exist yet), or `path` itself.
inline std::filesystem::path link_target(const std::filesystem::path& path) {
  std::error_code e;
  std::filesystem::path file = path;
  for (int hops = 0; std::filesystem::is_symlink(std::filesystem::symlink_status(file, e));
       ++hops) {
    if (hops == 40) cannot_write(path.string(), ELOOP);
    const std::filesystem::path next = std::filesystem::read_symlink(file, e);
    if (e) cannot_write(path.string(), e.value());
    file = next.is_absolute() ? next : file.parent_path() / next;
  }
  return file;
}

// In place, truncating: for what has no old contents to keep (a device, a pipe), and for a
// writable file in a folder where no new file can be made.
inline void write_in_place(const std::string& path, const std::string& file,
                           std::span<const std::byte> bytes) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
  if (fd < 0) cannot_write(path, errno);
  const bool written = write_all(fd, bytes);
  const int error = errno;
  if (::close(fd) != 0 && written) cannot_write(path, errno);
  if (!written) cannot_write(path, error);
}

}  // namespace detail

// Writes `bytes` as the file `path`, or throws std::runtime_error "PATH: cannot write: CAUSE" and
// leaves what was there. A new or regular file is written beside it, as FILE.part with the old
// file's permissions, and renamed over it; a symbolic link is followed, and the file it names
// replaced so (the link stays a link). A device or a pipe is written as it is. FILE.part is created
// anew (O_EXCL | O_NOFOLLOW): one that is there, left by an interrupted write or a link that would
// send the bytes elsewhere, is refused and left alone. A file the user may not write is refused,
// as opening it would be; a writable file in a folder where no new file can be made (so no
// FILE.part) is written in place, without the guarantee.
inline void replace_file(const std::string& path, std::span<const std::byte> bytes) {
  const std::filesystem::path target = detail::link_target(path);
  const std::string file = target.string();
  struct stat old {};
  const bool exists = ::stat(file.c_str(), &old) == 0;
  if (exists && !S_ISREG(old.st_mode)) return detail::write_in_place(path, file, bytes);
  if (exists && ::access(file.c_str(), W_OK) != 0) detail::cannot_write(path, errno);
  const std::string part = file + ".part";
  const int fd = ::open(part.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW, 0666);
  if (fd < 0 && errno == EEXIST)
    throw std::runtime_error(path + ": cannot write (" + part +
                             " exists: left by an interrupted write?)");
  if (fd < 0 && errno == EACCES && exists) return detail::write_in_place(path, file, bytes);
  if (fd < 0) detail::cannot_write(path, errno);
  const bool moded = !exists || ::fchmod(fd, old.st_mode & 07777) == 0;
  const bool written = moded && detail::write_all(fd, bytes);
  int error = errno;
  const bool closed = ::close(fd) == 0;
  if (written && !closed) error = errno;
  if (written && closed && std::rename(part.c_str(), file.c_str()) == 0) return;
  if (written && closed) error = errno;
  std::error_code e;
  std::filesystem::remove(part, e);
  detail::cannot_write(path, error);
}

inline void replace_file(const std::string& path, std::string_view text) {
  replace_file(path, std::as_bytes(std::span(text.data(), text.size())));
}

}  // namespace tp::host
