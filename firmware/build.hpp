// What the build's optimisation goal changes in the firmware: code copied for speed. A speed build
// (-O2) forces the per-pixel helpers inline (TP_PIXEL_INLINE), unrolls the small loops it is
// given unrolled forms of, and has a pixel loop instance for every combination of pixel format,
// depth test, write counts and depth saturation, so that no pixel branches on them. A size build
// (TP_SIZE_BUILD, fixedpoint/build_goal.hpp: -Os by default) leaves the inlining to the compiler
// (the Cortex-M size images ask it to inline less: TP_SIZE_FLAGS in target/CMakeLists.txt), takes
// the general loops, and has one pixel loop per colour source that reads the draw's state per pixel
// (firmware/draw.cpp, PixelWriter; docs/TARGET.md, "Footprint"). The arithmetic is the same in
// both, and so is every image.
#pragma once

#include "fixedpoint/build_goal.hpp"

namespace tp::fw {

#if TP_SIZE_BUILD
inline constexpr bool kSizeBuild = true;
#define TP_PIXEL_INLINE
// A small helper of 64-bit arithmetic that GCC at -Os would still copy into each caller, kept
// out of line in size builds (as fixedpoint/q.hpp's TP_FX_OUTLINE).
#define TP_SIZE_OUTLINE [[gnu::noinline]]
#define TP_UNROLL_XYZ
#else
inline constexpr bool kSizeBuild = false;
// A helper of a pixel loop, inlined into it in speed builds.
#define TP_PIXEL_INLINE [[gnu::always_inline]]
#define TP_SIZE_OUTLINE
// A pixel loop's loop over x, y and z (or the three channels), unrolled on the desktop: GCC -O2
// kept PointShader's stepping of its six sums a loop over memory on x86, 24 instructions a pixel
// where six additions do, and its sum of the three channels (totals) a loop of 11 instructions a
// channel. On the Cortex-M the unrolled stepper was slower (Phong up to 0.9 % more guest
// instructions per pixel) and 268 bytes larger, so the Arm images keep the loops
// (docs/DECISIONS.md, "The root seed's segments and the stepper unrolled", "The exact shader's
// channel sums unrolled").
#if defined(__arm__)
#define TP_UNROLL_XYZ
#else
#define TP_UNROLL_XYZ _Pragma("GCC unroll 3")
#endif
#endif

}  // namespace tp::fw
