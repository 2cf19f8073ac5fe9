// Writing a whole output file, for every file the tools write (command streams, images, the stress
// suite's JSON and bounds): a regular file holds all the new bytes or is as it was. A write that
// fails part-way (a full disk, the file size limit) throws naming the file and the cause and
// leaves the old file, not a file cut short (replace_file says where this cannot hold).
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

#include "host/file_identity.hpp"

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

// Where a chain of symbolic links ends (a file that may not exist yet), or `path` itself; and
// whether the chain passes through /proc, whose links (/dev/stdout -> /proc/self/fd/1) name open
// descriptors, not paths.
struct LinkEnd {
  std::filesystem::path file;
  bool link = false, descriptor = false;
};
inline LinkEnd link_end(const std::filesystem::path& path) {
  std::error_code e;
  LinkEnd end{path};
  for (int hops = 0; std::filesystem::is_symlink(std::filesystem::symlink_status(end.file, e));
       ++hops) {
    if (hops == 40) cannot_write(path.string(), ELOOP);
    const std::filesystem::path next = std::filesystem::read_symlink(end.file, e);
    if (e) cannot_write(path.string(), e.value());
    end.file = next.is_absolute() ? next : end.file.parent_path() / next;
    end.link = true;
    end.descriptor = end.descriptor || end.file.string().starts_with("/proc/");
  }
  return end;
}

// In place, truncating, the kernel following any link: for what has no old contents to keep (a
// device, a pipe, an open descriptor, a new file at the end of a link) and for a writable file in
// a folder where no new file can be made. `created`: the file this call makes, removed if the
// write fails.
inline void write_in_place(const std::string& path, std::span<const std::byte> bytes,
                           const std::string& created = {}) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0666);
  if (fd < 0) cannot_write(path, errno);
  const bool written = write_all(fd, bytes);
  int error = errno;
  const bool closed = ::close(fd) == 0;
  if (written && closed) return;
  if (written) error = errno;
  if (!created.empty()) ::unlink(created.c_str());
  cannot_write(path, error);
}

// A new file's owner, group and permissions as the old file's, as far as the writer may: the
// owner only for root; never set-user-ID or set-group-ID (images and streams are no programs).
inline bool take_mode(int fd, const struct stat& old) {
  if (::fchown(fd, old.st_uid, old.st_gid) != 0)
    (void)::fchown(fd, static_cast<uid_t>(-1), old.st_gid);
  return ::fchmod(fd, old.st_mode & 01777) == 0;
}

[[noreturn]] inline void stale_part(const std::string& path, const std::string& part) {
  throw std::runtime_error(path + ": cannot write (" + part +
                           " exists: left by an interrupted write?)");
}

// The bytes to a file without a name in `file`'s folder (O_TMPFILE), which is then linked as
// `part` and renamed over `file`: a run killed before the link leaves nothing behind. false, with
// nothing written anywhere, where the file system has no unnamed files or /proc is not there to
// link one by: the caller then makes `part` by its name. `old`: the file there now, if any.
inline bool replace_unnamed(const std::string& path, const std::string& file,
                            const std::string& part, std::span<const std::byte> bytes,
                            const struct stat* old) {
  std::filesystem::path folder = std::filesystem::path(file).parent_path();
  if (folder.empty()) folder = ".";
  const int fd = ::open(folder.c_str(), O_TMPFILE | O_WRONLY, 0666);
  if (fd < 0 && (errno == EOPNOTSUPP || errno == EISDIR || errno == EINVAL)) return false;
  if (fd < 0 && errno == EACCES && old != nullptr) {
    write_in_place(path, bytes);  // a writable file in a folder where no new file can be made
    return true;
  }
  if (fd < 0) cannot_write(path, errno);
  const bool written = (old == nullptr || take_mode(fd, *old)) && write_all(fd, bytes);
  int error = errno;
  const std::string self = "/proc/self/fd/" + std::to_string(fd);
  const bool linked =
      written && ::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, part.c_str(), AT_SYMLINK_FOLLOW) == 0;
  if (written && !linked) error = errno;
  const bool closed = ::close(fd) == 0;
  if (linked && !closed) error = errno;
  if (linked && closed && std::rename(part.c_str(), file.c_str()) == 0) return true;
  if (linked && closed) error = errno;
  if (linked) ::unlink(part.c_str());
  if (written && !linked && error == EEXIST) stale_part(path, part);
  std::error_code e;
  if (written && !linked && error == ENOENT && !std::filesystem::exists("/proc/self/fd", e))
    return false;
  cannot_write(path, error);
}

}  // namespace detail

// Writes `bytes` as the file `path`, or throws std::runtime_error "PATH: cannot write: CAUSE".
// A regular file, or a new one, is replaced whole or not at all. The bytes go to a file beside it
// that has no name yet (O_TMPFILE), with the old file's owner, group and permissions as far as the
// writer may set them; once all of them are written it is linked as FILE.part and renamed over
// FILE. A failed write leaves FILE as it was and nothing beside it, and so does a run killed while
// it writes. A FILE.part that is there (left by an older tool or by a run killed between the link
// and the rename, or a link that would send the bytes elsewhere) is refused and left alone. Where
// the file system has no unnamed files, FILE.part is made by its name (O_EXCL | O_NOFOLLOW) and
// written the same way, but a killed run leaves it. A symbolic link to a regular file is followed
// by the kernel first (so its protections of links in shared folders hold), and the file it names
// is replaced so; the link stays a link. Written in place instead, without the guarantee: a
// device, a pipe or an open descriptor (/dev/stdout), a new file at the end of a link, and a
// writable file in a folder where no new file can be made. A file the user may not write is
// refused, as opening it would be, and so is another user's file in a sticky folder (/tmp), which
// the kernel lets no one else rename over.
inline void replace_file(const std::string& path, std::span<const std::byte> bytes) {
  struct stat old {};
  const bool exists = ::stat(path.c_str(), &old) == 0;  // through links, as the kernel follows them
  if (!exists && errno != ENOENT) detail::cannot_write(path, errno);
  const detail::LinkEnd end = detail::link_end(path);
  const std::string file = end.file.string();
  if (end.descriptor || (exists && (!S_ISREG(old.st_mode) || old.st_nlink == 0)))
    return detail::write_in_place(path, bytes);
  if (!exists && end.link) return detail::write_in_place(path, bytes, file);
  if (exists && !same_file(path, file))
    return detail::write_in_place(path, bytes);  // not where the links seemed to lead: as it is
  if (exists && ::access(file.c_str(), W_OK) != 0) detail::cannot_write(path, errno);
  const std::string part = file + ".part";
  if (detail::replace_unnamed(path, file, part, bytes, exists ? &old : nullptr)) return;
  const int fd = ::open(part.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW, 0666);
  if (fd < 0 && errno == EEXIST) detail::stale_part(path, part);
  if (fd < 0 && errno == EACCES && exists) return detail::write_in_place(path, bytes);
  if (fd < 0) detail::cannot_write(path, errno);
  const bool moded = !exists || detail::take_mode(fd, old);
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
