// The main of every benchmark program: Google Benchmark's own, plus the build's fingerprint in the context, since
// figures of builds with different numbers (another float mode, another Box2D) are not comparable.

#include <benchmark/benchmark.h>

#include "common/program/build_fingerprint.h"

int main(int argc, char** argv) {
  benchmark::AddCustomContext("fingerprint", poet::build_fingerprint_line());
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
