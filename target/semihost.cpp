#include "target/semihost.hpp"

#include <cstring>

#include "fixedpoint/divide.hpp"

namespace tp::target {
namespace {

constexpr int kSysOpen = 0x01;
constexpr int kSysClose = 0x02;
constexpr int kSysWrite0 = 0x04;
constexpr int kSysWrite = 0x05;
constexpr int kSysRead = 0x06;
constexpr int kSysFlen = 0x0c;
constexpr int kSysGetCmdline = 0x15;
constexpr int kSysExit = 0x18;
// SYS_OPEN's modes, the index of the ISO C fopen mode in the semihosting specification's list.
constexpr std::uintptr_t kModeReadBinary = 1;   // "rb"
constexpr std::uintptr_t kModeWriteBinary = 5;  // "wb"
// SYS_EXIT reasons (Arm semihosting spec): on AArch32 the reason is the only argument, and QEMU
// maps ApplicationExit to status 0 and anything else to 1.
constexpr std::uintptr_t kApplicationExit = 0x20026;
constexpr std::uintptr_t kRunTimeErrorUnknown = 0x20023;

int call(int op, const void* arg) {
  register int r0 asm("r0") = op;
  register const void* r1 asm("r1") = arg;
  asm volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}

// The calls that take several arguments get them as a block of words (r1 points to it).
int call_block(int op, std::uintptr_t a, std::uintptr_t b, std::uintptr_t c) {
  const std::uintptr_t block[3] = {a, b, c};
  return call(op, block);
}
std::uintptr_t address(const void* p) { return reinterpret_cast<std::uintptr_t>(p); }

}  // namespace

void write(const char* text) { call(kSysWrite0, text); }

void write_dec(std::uint64_t value) {
  char buf[24];
  char* p = buf + sizeof buf - 1;
  *p = '\0';
  do {  // fx::udivmod: the images link no 64-bit division helper (target.*.no_division_helper)
    const tp::fx::UDivMod digit = tp::fx::udivmod(value, 10u);
    *--p = static_cast<char>('0' + digit.rem);
    value = digit.quot;
  } while (value != 0);
  write(p);
}

void write_hex64(std::uint64_t value) {
  char buf[17];
  buf[16] = '\0';
  for (int i = 15; i >= 0; --i, value >>= 4) buf[i] = "0123456789abcdef"[value & 15u];
  write(buf);
}

bool command_line(char* buffer, std::size_t size) {
  // In: the buffer and its size; out: the length of the line, without its NUL.
  std::uintptr_t block[2] = {address(buffer), size};
  return size > 0 && call(kSysGetCmdline, block) == 0 && block[1] < size;
}

int open_file(const char* path, bool for_writing) {
  return call_block(kSysOpen, address(path), for_writing ? kModeWriteBinary : kModeReadBinary,
                    std::strlen(path));
}

bool file_length(int handle, std::uint32_t& bytes) {
  const std::uintptr_t block[1] = {static_cast<std::uintptr_t>(handle)};
  bytes = static_cast<std::uint32_t>(call(kSysFlen, block));
  return bytes != 0xffffffffu;
}

std::size_t read_file(int handle, void* buffer, std::size_t size) {
  // Returns the bytes not read: `size` at the end of the file, and on an error.
  const auto left = static_cast<std::size_t>(
      call_block(kSysRead, static_cast<std::uintptr_t>(handle), address(buffer), size));
  return left <= size ? size - left : 0;
}

bool write_file(int handle, const void* data, std::size_t size) {
  return call_block(kSysWrite, static_cast<std::uintptr_t>(handle), address(data), size) == 0;
}

void close_file(int handle) {
  const std::uintptr_t block[1] = {static_cast<std::uintptr_t>(handle)};
  call(kSysClose, block);
}

void exit(bool success) {
  call(kSysExit, reinterpret_cast<const void*>(success ? kApplicationExit : kRunTimeErrorUnknown));
  for (;;) {
  }
}

}  // namespace tp::target
