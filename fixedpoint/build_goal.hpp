// The build's goal, size or speed, as one macro that fixedpoint/ and firmware/ read:
// TP_SIZE_BUILD is 1 in a size build, which keeps one out-of-line copy of small helpers and takes
// general loops instead of copies made for speed (fixedpoint/q.hpp, firmware/build.hpp), and 0
// in a speed build. By default it follows the compiler's goal (-Os defines __OPTIMIZE_SIZE__); a
// port may set it, as the small parts' builds do (m3-Os-tiny: -DTP_SIZE_BUILD=0, the speed
// source compiled at -Os; docs/TARGET.md, "A small part's speed"). Every translation unit of one
// image must see the same value: inline functions and templates differ between the two, and the
// linker would keep whichever copy it met first.
#pragma once

#ifndef TP_SIZE_BUILD
#ifdef __OPTIMIZE_SIZE__
#define TP_SIZE_BUILD 1
#else
#define TP_SIZE_BUILD 0
#endif
#endif
