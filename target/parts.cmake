# The small parts' builds, read by target/CMakeLists.txt (their images) and tests/target (their
# tests): the methods each links and the device's TP_FIRMWARE_METHODS mask that links them, bit
# id for method id of firmware/types.hpp (flat 1, gouraud 2, kb 6, kb-adaptive 13). A name here
# that the mask leaves out fails its image's tests: its set_method is refused.
#
# m3-Os-small: the M3 at -Os with what a part with 48 KiB for code would ship (docs/TARGET.md,
# "Code by method"). m3-Os-tiny: a part with 48 KiB for code and 64 KiB of RAM, two lights
# (docs/TARGET.md, "A small part").
set(TP_PART_CONFIGS m3-Os-small m3-Os-tiny)
set(TP_LINKED_m3-Os-small flat gouraud kb-adaptive)
set(TP_MASK_m3-Os-small "((1ull<<1)|(1ull<<2)|(1ull<<13))")
set(TP_LINKED_m3-Os-tiny flat gouraud kb)
set(TP_MASK_m3-Os-tiny "((1ull<<1)|(1ull<<2)|(1ull<<6))")
