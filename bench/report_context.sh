#!/bin/sh
# A benchmark report names the SIMD kernels the runtime picked (bench_main.h), and bench/run.sh refuses
# a report name that is not a plain word before it runs anything.
#   sh bench/report_context.sh PROGRAM FILTER
set -u
program="$1" filter="$2"
here="$(cd "$(dirname "$0")" && pwd)"
. "$here/check_failure.sh"
report="$("$program" --benchmark_filter="$filter" --benchmark_min_time=0.001 --benchmark_format=json)" || {
  echo "$program failed" >&2
  exit 1
}
case "$report" in
  *'"instruction_set": "scalar"'* | *'"instruction_set": "sse4.1"'* | *'"instruction_set": "avx2"'* | \
    *'"instruction_set": "avx512"'* | *'"instruction_set": "neon"'*) ;;
  *) echo "the report's context names no instruction set" >&2; exit 1 ;;
esac
message="$(bash "$here/run.sh" /nonexistent-build "../escape" 2>&1)"
code=$?
check_failure "bench/run.sh with the name '../escape'" 2 "letters, digits, '-' and '_' only" "$code" "$message"
