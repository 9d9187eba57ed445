// poet-libm-fingerprint: the build's fingerprint as it would be with the C library's exp, log, sin and cos in
// place of the project's (math/c_library_math.cpp on the link line). masked_processor_test runs it under glibc's
// processor masks to show that the arithmetic probe sees what the C library changes, where the project's build
// computes the same digest.

#include <cstdio>

#include "common/program/build_fingerprint.h"

int main() {
  std::fputs(poet::build_fingerprint().c_str(), stdout);
  return 0;
}
