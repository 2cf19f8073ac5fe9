// Whether everything a program wrote to standard output reached it. A report redirected to a full
// disk (`tinyphong replay --hash *.tpcmd > hashes.txt`, `tinyphong-results > results.md`) was
// lost without a word and the exit status was 0 (the bench programs until 2026-12-08).
#pragma once

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>

namespace tp::host {

// Flushes standard output; if anything written to it was lost, says so on standard error as
// `program` and returns false: the caller exits non-zero.
inline bool standard_output_written(const char* program) {
  errno = 0;
  std::cout.flush();
  const bool flushed = std::fflush(stdout) == 0 && !std::cout.fail();
  if (flushed && std::ferror(stdout) == 0) return true;
  const int error = errno;
  std::cerr << program << ": standard output: cannot write"
            << (error != 0 ? std::string(": ") + std::strerror(error) : std::string()) << "\n";
  return false;
}

}  // namespace tp::host
