// tinyobjloader's implementation, compiled into the fuzz build with the instrumentation, so that
// the fuzzer sees its branches and ASan its memory (Debian's shared library is neither).
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
