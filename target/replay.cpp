// A Cortex-M image that replays any command stream from the host, as a board is fed one over a
// link: semihosting opens the .tpcmd file named on the image's command line and reads it in
// chunks, and the device executes each chunk's whole commands, carrying the command cut by the
// chunk's end over to the next. No stream is built in, so any frame `tinyphong record` writes
// runs on the core without building an image for it (docs/TARGET.md, "Any stream on the core"):
//
//   qemu-system-arm -M mps2-an385 -nographic -monitor none
//       -semihosting-config enable=on,target=native -kernel m3-O2-replay.elf
//       -append "FRAME.tpcmd [FRAME.ppm] [--chunk WORDS]"
//
// prints, as the images with embedded streams do (target/main.cpp),
//     stream FRAME.tpcmd HASH                        (FNV-1a 64, as `tinyphong replay --hash`)
// or  stream FRAME.tpcmd error CODE at word OFFSET   (the offset in the whole file)
// or, for a file that is not a whole number of words or cannot be read to its end, a message
// naming it and no frame,
// then the stack's high-water mark and "done"; exits with success iff the stream ran. With
// FRAME.ppm it writes the frame as a binary PPM (RGB565 widened by bit replication, as the host's
// PNG). --chunk sets the words read at a time (at most kMaxChunkWords): the tests cut the stream
// at every few words to show that where the link cuts it changes nothing.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <new>
#include <span>

#include "firmware/device.hpp"
#include "target/report.hpp"
#include "target/semihost.hpp"
#include "target/stack_mark.hpp"

// As target/main.cpp: the largest stream at the scenes' own resolutions fits.
#ifndef TP_BLOCK_BYTES
#define TP_BLOCK_BYTES (7u << 19)
#endif
#ifndef TP_IMAGE_NAME
#define TP_IMAGE_NAME "tinyphong"
#endif

namespace {

using tp::fw::Device;
using tp::fw::Error;

constexpr std::size_t kMaxChunkWords = 16384;
// The longest command: a header and 0xffff payload words (the length field is 16 bits).
constexpr std::size_t kMaxCommandWords = 1 + 0xffff;

alignas(8) __attribute__((section(".noinit"))) std::byte block[TP_BLOCK_BYTES];
alignas(Device) __attribute__((section(".noinit"))) unsigned char device_storage[sizeof(Device)];
// A command cut by a chunk's end waits here for the rest: at most kMaxCommandWords - 1 words of
// it, then a chunk.
__attribute__((section(".noinit"))) std::uint32_t words[kMaxCommandWords + kMaxChunkWords];
// One row of the PPM.
__attribute__((section(".noinit"))) std::uint8_t ppm_row[3 * tp::fw::kMaxDimension];

struct Arguments {
  const char* stream = nullptr;
  const char* ppm = nullptr;
  std::size_t chunk_words = kMaxChunkWords;
};

// A decimal count from 1 to kMaxChunkWords; 0 if the text is not one.
std::size_t chunk_words(const char* text) {
  std::size_t v = 0;
  for (const char* d = text; *d != '\0'; ++d) {
    if (*d < '0' || *d > '9' || v > kMaxChunkWords) return 0;
    v = 10 * v + static_cast<std::size_t>(*d - '0');
  }
  return v <= kMaxChunkWords ? v : 0;
}

// The command line's words after the image's path, NUL-terminated in place; false (after a
// message) if they are not the usage's.
bool parse(char* line, Arguments& args) {
  using namespace tp::target;
  const char* word[8];
  int n = 0;
  for (char* p = line; *p != '\0';) {
    while (*p == ' ') *p++ = '\0';
    if (*p == '\0') break;
    if (n == 8) {
      write("too many arguments\n");
      return false;
    }
    word[n++] = p;
    while (*p != ' ' && *p != '\0') ++p;
  }
  for (int i = 1; i < n; ++i) {
    if (std::strcmp(word[i], "--chunk") == 0) {
      args.chunk_words = i + 1 < n ? chunk_words(word[++i]) : 0;
      if (args.chunk_words == 0) {
        write("--chunk: a count of words from 1 to 16384\n");
        return false;
      }
    } else if (args.stream == nullptr) {
      args.stream = word[i];
    } else if (args.ppm == nullptr) {
      args.ppm = word[i];
    } else {
      write("unexpected argument: ");
      write(word[i]);
      write("\n");
      return false;
    }
  }
  if (args.stream != nullptr) return true;
  write("usage (-append): FRAME.tpcmd [FRAME.ppm] [--chunk WORDS]\n");
  return false;
}

// The whole commands at the start of words[0, count): how many words they take.
std::size_t whole_commands(std::size_t count) {
  std::size_t at = 0;
  while (at < count && (words[at] >> 16) < count - at) at += 1 + (words[at] >> 16);
  return at;
}

// Where feeding a file stopped: the device's error and the word of the file it stopped at (kOk
// and the file's length in words if every command ran), or the bytes read before a read failed.
struct Fed {
  Error error = Error::kOk;
  std::size_t word = 0;
  bool read_all = true;
  std::size_t bytes_read = 0;
};

// Feeds the file, `length` bytes (a whole number of words), to the device chunk by chunk, up to
// the first command that fails.
Fed feed(Device& device, int file, std::size_t length, const Arguments& args) {
  std::size_t bytes = 0;       // in words[], from its start
  std::size_t done_words = 0;  // of the file, executed before words[0]
  std::size_t read = 0;        // of the file
  for (;;) {
    const std::size_t got = tp::target::read_file(file, reinterpret_cast<std::byte*>(words) + bytes,
                                                  4 * args.chunk_words);
    bytes += got;
    read += got;
    const std::size_t whole = whole_commands(bytes / 4);
    if (whole > 0) {
      if (const Error e = device.execute(std::span<const std::uint32_t>(words, whole));
          e != Error::kOk)
        return {e, done_words + device.words_consumed()};
      done_words += whole;
      bytes -= 4 * whole;
      std::memmove(words, words + whole, bytes);
    }
    if (got > 0) continue;
    // The end of the file, or a read that failed: a frame of the commands before it is not the
    // file's frame.
    if (read != length) return {Error::kOk, done_words, false, read};
    if (bytes == 0) return {Error::kOk, done_words};
    // A last command that the file cuts short: the device names the fault (its opcode or its
    // length), as it would in one call.
    const Error e = device.execute(std::span<const std::uint32_t>(words, bytes / 4));
    return {e, done_words + device.words_consumed()};
  }
}

// The frame as a binary PPM, its rows as the host's images take them (row_as_rgb888).
bool write_ppm(const tp::fw::FramebufferView& fb, const char* path) {
  using namespace tp::target;
  const int file = open_file(path, true);
  if (file < 0) return false;
  char header[32] = "P6\n";
  char* p = header + 3;
  const auto append = [&p](std::uint32_t v, char after) {
    char digits[10];
    int n = 0;
    do {
      digits[n++] = static_cast<char>('0' + v % 10u);
      v /= 10u;
    } while (v != 0);
    while (n > 0) *p++ = digits[--n];
    *p++ = after;
  };
  append(fb.width, ' ');
  append(fb.height, '\n');
  append(255, '\n');
  bool ok = write_file(file, header, static_cast<std::size_t>(p - header));
  for (std::uint32_t y = 0; ok && y < fb.height; ++y) {
    tp::fw::row_as_rgb888(fb, y, ppm_row);
    ok = write_file(file, ppm_row, 3 * std::size_t{fb.width});
  }
  close_file(file);
  return ok;
}

bool run(const Arguments& args) {
  using namespace tp::target;
  const int file = open_file(args.stream, false);
  if (file < 0) {
    write("stream ");
    write(args.stream);
    write(": cannot open\n");
    return false;
  }
  // As the host's replay (read_command_file): a file that ends inside a word runs nothing.
  std::uint32_t length = 0;
  const bool known = file_length(file, length);
  if (!known || length % 4 != 0) {
    close_file(file);
    write("stream ");
    write(args.stream);
    if (!known) {
      write(": cannot read its length\n");
    } else {
      write(": ");
      write_dec(length);
      write(" bytes is not a whole number of 32-bit words (a truncated file?)\n");
    }
    return false;
  }
  auto* device = new (device_storage) Device(std::span<std::byte>(block, sizeof block));
  const Fed fed = feed(*device, file, length, args);
  close_file(file);
  bool ok = false;
  if (!fed.read_all) {
    write("stream ");
    write(args.stream);
    write(": read error after ");
    write_dec(fed.bytes_read);
    write(" of ");
    write_dec(length);
    write(" bytes\n");
  } else {
    ok = report_stream(args.stream, *device, fed.error, fed.word);
  }
  if (ok && args.ppm != nullptr && !write_ppm(device->framebuffer(), args.ppm)) {
    write(args.ppm);
    write(": cannot write\n");
    ok = false;
  }
  device->~Device();
  return ok;
}

}  // namespace

int main() {
  using namespace tp::target;
  write("tinyphong replay image " TP_IMAGE_NAME ": sizeof(Device) = ");
  write_dec(sizeof(Device));
  write(", block = ");
  write_dec(sizeof block);
  write("\n");
  paint_stack();
  static char line[1024];
  Arguments args;
  if (!command_line(line, sizeof line)) {
    write("the command line does not fit 1024 bytes\n");
    return 1;
  }
  const bool ok = parse(line, args) && run(args);
  write("stack high-water mark ");
  write_dec(stack_used_bytes());
  write(" bytes\n");
  write(ok ? "done\n" : "done with errors\n");
  return ok ? 0 : 1;
}
