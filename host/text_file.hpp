// Reading a whole input file with a size limit, for the scene and OBJ readers: a file over the
// limit is refused before it is held in memory, whatever size the file system reports (files
// under /proc report 0 and can be far larger).
#pragma once

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

namespace tp::host {

enum class ReadResult { ok, cannot_open, too_large, not_regular };

// What a reader takes: any file it can open (the CLI reads `render <(…)`, a pipe, and waits on a
// FIFO as `cat` does), or a regular file alone, checked on the open descriptor itself: a FIFO put
// in place of a file between a check by name and the open blocked the opening thread (the
// server's render loop; found by review, 2026-12-07). For a regular file alone the open does not
// block, whatever the file is.
enum class Accept { any_file, regular_file };

namespace detail {

// Appends blocks from `read_block` (bytes read, 0 at the end, < 0 on an error) until the end.
template <class ReadBlock>
ReadResult read_blocks(std::uintmax_t max_bytes, std::string& text, ReadBlock read_block) {
  text.clear();
  char block[1 << 16];
  for (;;) {
    const long n = read_block(block, sizeof block);
    if (n < 0) return ReadResult::cannot_open;
    if (n == 0) return ReadResult::ok;
    text.append(block, static_cast<std::size_t>(n));
    if (text.size() > max_bytes) return ReadResult::too_large;
  }
}

// An open descriptor, closed however the read ends (a full memory throws from the append), the
// reason of a failed read kept.
class Descriptor {
 public:
  explicit Descriptor(int fd) : fd_(fd) {}
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  ~Descriptor() {
    if (fd_ < 0) return;
    const int saved = errno;
    ::close(fd_);
    errno = saved;
  }
  int get() const { return fd_; }

 private:
  int fd_;
};

inline ReadResult read_regular_file(const std::filesystem::path& file, std::uintmax_t max_bytes,
                                    std::string& text) {
  const Descriptor fd(::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC));
  if (fd.get() < 0) return ReadResult::cannot_open;
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) return ReadResult::cannot_open;
  if (!S_ISREG(st.st_mode)) return ReadResult::not_regular;
  return read_blocks(max_bytes, text, [&fd](char* block, std::size_t size) -> long {
    for (;;) {
      const ssize_t n = ::read(fd.get(), block, size);
      if (n >= 0 || errno != EINTR) return static_cast<long>(n);
    }
  });
}

}  // namespace detail

// Reads `file` into `text`; too_large (and `text` unspecified) when it holds more than
// max_bytes bytes, not_regular when `accept` asks for a regular file and it is not one. Reads in
// blocks, so that at most max_bytes + one block is ever held. On cannot_open, *os_error (if given)
// is the system's reason (errno), for the message: "cannot open scene file" alone did not say
// whether the file was missing or unreadable.
inline ReadResult read_text_file(const std::filesystem::path& file, std::uintmax_t max_bytes,
                                 std::string& text, int* os_error = nullptr,
                                 Accept accept = Accept::any_file) {
  errno = 0;
  ReadResult r = ReadResult::cannot_open;
  if (accept == Accept::regular_file) {
    r = detail::read_regular_file(file, max_bytes, text);
  } else if (std::ifstream in(file, std::ios::binary); in) {
    r = detail::read_blocks(max_bytes, text, [&in](char* block, std::size_t size) -> long {
      if (in.read(block, static_cast<std::streamsize>(size)) || in.gcount() > 0)
        return static_cast<long>(in.gcount());
      return in.bad() ? -1 : 0;
    });
  }
  if (r == ReadResult::cannot_open && os_error != nullptr) *os_error = errno;
  return r;
}

// The reason read_text_file gave, for a message: " (No such file or directory)", or nothing.
inline std::string os_reason(int os_error) {
  return os_error != 0 ? " (" + std::generic_category().message(os_error) + ")" : std::string();
}

}  // namespace tp::host
