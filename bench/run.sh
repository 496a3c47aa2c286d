#!/usr/bin/env bash
# Runs the benchmarks in BUILD_DIR and writes docs/PERFORMANCE.md: medians of repeated runs, and
# every figure also as a ratio to a baseline measured in the same run (absolute times on shared
# machines drift by tens of percent; ratios within one run are what we compare).
#   bash bench/run.sh BUILD_DIR          the run of record: docs/PERFORMANCE.md
#   bash bench/run.sh BUILD_DIR NAME     another CPU's report: docs/PERFORMANCE_NAME.md (NAME: letters,
#                                        digits, '-' and '_'; say what sets the CPU apart, e.g. avx2)
set -euo pipefail
build="${1:?usage: bench/run.sh BUILD_DIR [NAME]}"
name="${2:-}"
if [ -n "$name" ] && ! [[ "$name" =~ ^[A-Za-z0-9_-]+$ ]]; then
  echo "bench/run.sh: the report's name may hold letters, digits, '-' and '_' only, got '$name'" >&2
  exit 2
fi
export DNG_REPORT_NAME="$name"
suffix="${name:+_$name}"
root="$(cd "$(dirname "$0")/.." && pwd)"
export DNG_BENCH_MESH="${DNG_BENCH_MESH:-$root/data/data/meshes/bunny00.off}"
# The CPU's model goes into every report's context (ratios between methods differ between CPU makers:
# gathers, divides and the BVH traversal do not scale alike). The flag takes comma-separated pairs.
cpu_model="$(grep -m1 '^model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2- | tr -d ',' | sed 's/^ *//')"
context="--benchmark_context=cpu_model=${cpu_model:-unknown}"
for program in field_query_bench particle_step_bench many_bodies_bench threads_bench bake_bench; do
  echo "bench/run.sh: running $program" >&2
  # The many-bodies and threads figures are ratios of rows: interleave the rows' repetitions so that
  # other work on the machine weighs on baseline and candidate alike.
  # Their ratios also sit near their goals, where this shared machine's slow and fast spells (a third
  # apart, tens of seconds long) moved a median of 5 across a goal between runs: 9 there.
  interleave=false repetitions=5
  case "$program" in many_bodies_bench | threads_bench) interleave=true repetitions=9 ;; esac
  "$build/bench/$program" "$context" --benchmark_min_time=0.3 --benchmark_repetitions="$repetitions" \
    --benchmark_enable_random_interleaving=$interleave \
    --benchmark_report_aggregates_only=true --benchmark_format=json >"$build/$program.json"
done
# Table 1 (bench/table1_bench.cpp): fandisk with 100k and 1M particles, then the triangle-count sweep at
# 100k on the extra meshes. Repetitions (9) run in random order so that the shared machine's drift falls
# on every method alike. About 8 minutes, most of it the 1M rows and baking the 871k-triangle dragon.
echo "bench/run.sh: running table1_bench" >&2
bash "$root/bench/fetch_table1_meshes.sh"
meshes="$(dirname "$DNG_BENCH_MESH")" extra="$root/data/table1"
"$build/bench/table1_bench" "$context" --table="$meshes/fandisk.off" --particles=100000,1000000 \
  --sweep="$extra/cow.off,$extra/dragon_res4.off,$meshes/bunny00.off,$extra/dragon_res2.off,$extra/dragon.off" \
  --sweep_particles=100000 --benchmark_min_time=0.2 --benchmark_repetitions=9 \
  --benchmark_enable_random_interleaving=true --benchmark_report_aggregates_only=true \
  --benchmark_format=json >"$build/table1_bench.json"
# The report and the plot are made beside the build and moved into docs/ only when all of them are
# whole: a run that fails half-way (a full disk, a benchmark that exits 2) leaves the last report.
report="$build/PERFORMANCE.md" plot="$build/table1_sweep.png"
python3 "$root/bench/report.py" "$build/field_query_bench.json" "$build/particle_step_bench.json" "$build/bake_bench.json" \
  "$build/table1_bench.json" "$build/many_bodies_bench.json" "$build/threads_bench.json" >"$report"
gnuplot -e "data='$build/table1_bench_sweep.dat'; out='$plot'" "$root/bench/table1_plot.gp"
echo "bench/run.sh: running accuracy_bench" >&2
"$build/bench/accuracy_bench" "$(dirname "$DNG_BENCH_MESH")" >>"$report"
# Both copied before either is renamed over the old one, so a failed copy leaves the old pair.
final_report="$root/docs/PERFORMANCE$suffix.md" final_plot="$root/docs/images/table1_sweep$suffix.png"
new_report="$final_report.new" new_plot="$final_plot.new"
trap 'rm -f "$new_report" "$new_plot"' EXIT
cp "$report" "$new_report"
cp "$plot" "$new_plot"
mv "$new_plot" "$final_plot"
mv "$new_report" "$final_report"
echo "bench/run.sh: wrote docs/PERFORMANCE$suffix.md" >&2
