// The console of the Cortex-M images: Arm semihosting (bkpt 0xab), which QEMU serves with
// `-semihosting-config enable=on,target=native`. Output and the exit status; and, for the replay
// image (target/replay.cpp), the image's command line and files on the host, opened in QEMU's
// working directory.
#pragma once

#include <cstddef>
#include <cstdint>

namespace tp::target {

void write(const char* text);           // SYS_WRITE0: a NUL-terminated string
void write_dec(std::uint64_t value);    // unsigned decimal
void write_hex64(std::uint64_t value);  // 16 lower-case hex digits, as hash_hex on the host
[[noreturn]] void exit(bool success);   // SYS_EXIT: QEMU exits 0 on success, 1 otherwise

// SYS_GET_CMDLINE: the image's command line, NUL-terminated (QEMU: the -kernel path, then the
// words of -append). False if it does not fit `size` bytes.
bool command_line(char* buffer, std::size_t size);
// SYS_OPEN in binary mode, for reading or for writing (created or truncated): a handle, or -1.
int open_file(const char* path, bool for_writing);
// SYS_FLEN: the file's length in bytes; false on an error (the call returns -1, which a 32-bit
// length of 4 GiB - 1 bytes would too).
bool file_length(int handle, std::uint32_t& bytes);
// SYS_READ: the bytes read into buffer, at most `size`; 0 at the end of the file, and on an error
// (which only the file's length then tells apart).
std::size_t read_file(int handle, void* buffer, std::size_t size);
// SYS_WRITE: whether all `size` bytes were written.
bool write_file(int handle, const void* data, std::size_t size);
void close_file(int handle);  // SYS_CLOSE

}  // namespace tp::target
