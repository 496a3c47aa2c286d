#!/bin/sh
# A benchmark program whose report cannot be written whole exits 2 and says so (bench_main.h): with
# Google Benchmark's own main it returned 0 with the report cut short.
#   sh bench/report_to_full_disk.sh PROGRAM FILTER
set -u
program="$1" filter="$2"
. "$(dirname "$0")/check_failure.sh"
[ -w /dev/full ] || { echo "no /dev/full here: skipped"; exit 77; }
message="$("$program" --benchmark_filter="$filter" --benchmark_min_time=0.001 --benchmark_format=json 2>&1 >/dev/full)"
code=$?
check_failure "standard output on /dev/full" 2 "cannot write the report to standard output" "$code" "$message"
