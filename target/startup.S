/* The Cortex-M vector table: initial stack pointer, reset, and the system exceptions. Every
 * exception but reset goes to fault_handler (target/startup.cpp), which reports it over
 * semihosting and exits: a fault ends the QEMU run at once instead of hanging to the timeout.
 * No interrupts are used. */
  .syntax unified
  .thumb

  .section .vectors, "a"
  .align 2
  .global vector_table
vector_table:
  .word __stack_top       /* initial SP */
  .word reset_handler
  .word fault_handler     /* NMI */
  .word fault_handler     /* HardFault */
  .word fault_handler     /* MemManage */
  .word fault_handler     /* BusFault */
  .word fault_handler     /* UsageFault */
  .word 0, 0, 0, 0
  .word fault_handler     /* SVCall */
  .word fault_handler     /* DebugMonitor */
  .word 0
  .word fault_handler     /* PendSV */
  .word fault_handler     /* SysTick */
