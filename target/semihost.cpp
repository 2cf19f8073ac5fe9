#include "target/semihost.hpp"

#include "fixedpoint/divide.hpp"

namespace tp::target {
namespace {

constexpr int kSysWrite0 = 0x04;
constexpr int kSysExit = 0x18;
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

void exit(bool success) {
  call(kSysExit, reinterpret_cast<const void*>(success ? kApplicationExit : kRunTimeErrorUnknown));
  for (;;) {
  }
}

}  // namespace tp::target
