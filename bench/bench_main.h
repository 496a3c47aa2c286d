// The benchmark programs' main: Google Benchmark's own, and then whether the report reached standard
// output. bench/run.sh sends each report to a file; on a full disk Google Benchmark's main still
// returned 0 with the JSON cut short, and the run failed only later, in report.py.
#pragma once

#include "dng/instruction_set.h"
#include "exit_codes.h"
#include "standard_output.h"

#include <benchmark/benchmark.h>

#include <cstdio>
#include <iostream>

namespace dng {
namespace bench {

/// Whether the report got to standard output: 0, or tools::kExitIo with a message on stderr when any of
/// it could not be written. For a main that runs the benchmarks itself; `program` names it.
inline int finishReport(const char* program) {
  if (!std::cout.flush()) {
    std::fprintf(stderr, "%s: error: cannot write the report to standard output\n", program);
    return tools::kExitIo;
  }
  return tools::finishStandardOutput(program, tools::kExitOk);
}

/// Records in the report's context the SIMD kernels the runtime picks on this CPU ("avx512", "avx2",
/// ...): the same code runs at very different speeds on CPUs with and without AVX-512, and the CPU's
/// model name alone ("AMD EPYC") does not tell them apart. Call after benchmark::Initialize.
inline void addInstructionSetContext() {
  benchmark::AddCustomContext("instruction_set", instructionSetName(bestInstructionSet()));
}

/// Runs the registered benchmarks under the Google Benchmark flags in argv. Returns 0; 1 for a flag it
/// does not know; tools::kExitIo when the report could not be written (finishReport).
inline int runBenchmarks(int argc, char** argv, const char* program) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  addInstructionSetContext();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return finishReport(program);
}

} // namespace bench
} // namespace dng
