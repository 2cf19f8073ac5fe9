// Reset and fault handlers of the Cortex-M images (the vector table is in startup.S), and the
// few C++ runtime hooks the firmware's virtual methods reference. No vendor SDK, no crt0:
// .data is copied from its load image, .bss zeroed, static constructors run, then main().
#include <cstddef>
#include <cstdint>

#include "target/semihost.hpp"

extern "C" {
extern std::uint32_t __data_load[], __data_start[], __data_end[], __bss_start[], __bss_end[];
extern void (*__init_array_start[])();
extern void (*__init_array_end[])();
int main();

[[noreturn]] void reset_handler() {
  // Plain loops (volatile stores): the compiler must not turn them into memcpy / memset
  // calls, whose code could in principle rely on the not-yet-initialised .data.
  const std::uint32_t* src = __data_load;
  for (volatile std::uint32_t* dst = __data_start; dst < __data_end;) *dst++ = *src++;
  for (volatile std::uint32_t* dst = __bss_start; dst < __bss_end;) *dst++ = 0;
  for (auto** f = __init_array_start; f < __init_array_end; ++f) (**f)();
  tp::target::exit(main() == 0);
}

[[noreturn]] void fault_handler() {
  tp::target::write("FAULT: an exception other than reset was taken\n");
  tp::target::exit(false);
}

// A pure virtual called: impossible in the firmware, but the vtables reference it.
[[noreturn]] void __cxa_pure_virtual() {
  tp::target::write("FAULT: pure virtual call\n");
  tp::target::exit(false);
}
}

// The deleting destructors of the firmware's polymorphic classes reference operator delete;
// nothing is ever allocated on the heap (the firmware has none), so it is never reached.
void operator delete(void*) noexcept { tp::target::exit(false); }
void operator delete(void*, std::size_t) noexcept { tp::target::exit(false); }
