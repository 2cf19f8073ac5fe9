// The console of the Cortex-M images: Arm semihosting (bkpt 0xab), which QEMU serves with
// `-semihosting-config enable=on,target=native`. Output only, and the exit status.
#pragma once

#include <cstdint>

namespace tp::target {

void write(const char* text);           // SYS_WRITE0: a NUL-terminated string
void write_dec(std::uint64_t value);    // unsigned decimal
void write_hex64(std::uint64_t value);  // 16 lower-case hex digits, as hash_hex on the host
[[noreturn]] void exit(bool success);   // SYS_EXIT: QEMU exits 0 on success, 1 otherwise

}  // namespace tp::target
