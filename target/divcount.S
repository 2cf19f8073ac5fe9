/* The cost images' count of 64-bit division helper calls (scripts/target-cost.sh, issue 12
 * item 6). Linked with -Wl,--wrap=__aeabi_ldivmod -Wl,--wrap=__aeabi_uldivmod, so that every
 * call the firmware makes lands here first: the counter is incremented and the real helper is
 * entered with r0-r3 and lr untouched (r12 is the call's scratch register under the AAPCS).
 * Each wrapper executes kDivWrapperInstructions = 7 instructions per call, which target/main.cpp
 * reports so that the cost script can leave them out of the draw's instruction count. */
  .syntax unified
  .thumb

  .section .bss.tp_div_calls, "aw", %nobits
  .align 2
  .global tp_ldivmod_calls
tp_ldivmod_calls:
  .space 4
  .global tp_uldivmod_calls
tp_uldivmod_calls:
  .space 4

  .text
  .align 1
  .global __wrap___aeabi_ldivmod
  .thumb_func
  .type __wrap___aeabi_ldivmod, %function
__wrap___aeabi_ldivmod:
  push {r0}
  ldr r0, =tp_ldivmod_calls
  ldr r12, [r0]
  add r12, r12, #1
  str r12, [r0]
  pop {r0}
  b.w __real___aeabi_ldivmod
  .size __wrap___aeabi_ldivmod, . - __wrap___aeabi_ldivmod

  .align 1
  .global __wrap___aeabi_uldivmod
  .thumb_func
  .type __wrap___aeabi_uldivmod, %function
__wrap___aeabi_uldivmod:
  push {r0}
  ldr r0, =tp_uldivmod_calls
  ldr r12, [r0]
  add r12, r12, #1
  str r12, [r0]
  pop {r0}
  b.w __real___aeabi_uldivmod
  .size __wrap___aeabi_uldivmod, . - __wrap___aeabi_uldivmod

  .ltorg
