#!/bin/sh
# A benchmark program whose report cannot be written whole exits 2 and says so (bench_main.h): with
# Google Benchmark's own main it returned 0 with the report cut short.
#   sh bench/report_to_full_disk.sh PROGRAM FILTER
set -u
program="$1" filter="$2"
[ -w /dev/full ] || { echo "no /dev/full here: skipped"; exit 77; }
message="$("$program" --benchmark_filter="$filter" --benchmark_min_time=0.001 --benchmark_format=json 2>&1 >/dev/full)"
code=$?
if [ "$code" -ne 2 ]; then
  echo "expected exit code 2 with standard output on /dev/full, got $code" >&2
  exit 1
fi
case "$message" in
  *"cannot write the report to standard output"*) exit 0 ;;
  *) echo "expected a message on standard error, got: $message" >&2; exit 1 ;;
esac
