"""Turns Google Benchmark JSON (with repetitions) into docs/PERFORMANCE.md."""
import json
import sys


def medians(path):
    with open(path) as f:
        data = json.load(f)
    out = {}
    for b in data["benchmarks"]:
        if b.get("aggregate_name") == "median":
            out[b["run_name"]] = (b["per_query"] * 1e9, b.get("label", ""))
    return data["context"], out


def main(path):
    context, m = medians(path)
    raw = {0: m["BM_RawArray/0"][0], 1: m["BM_RawArray/1"][0]}
    nano = {k: m.get("BM_NanoVdb/%d" % k, (None,))[0] for k in (0, 1)}
    print("# Performance\n")
    print("Written by `bash setup.sh bench` (bench/run.sh); do not edit by hand. Medians of 5 repetitions, "
          "measured on %s (%d CPUs, %s). Absolute times on shared machines drift by tens of percent between "
          "runs; the ratios to baselines measured in the same run are the figures to compare.\n"
          % (context.get("host_name", "?"), context.get("num_cpus", 0), context.get("date", "?")))
    print("## Field queries (bench/field_query_bench.cpp)\n")
    print("A 128^3 sphere field (radius 48 voxels, band 3 voxels); the same ~116k points within 2 voxels of the "
          "surface, in scan order (coherent) and shuffled (random), sampled with `View::sampleBatch`.\n")
    print("Baselines: **raw array**: the voxel's float4 from a bare array (bounds check, no refinement, no "
          "validation: the paper's plain normal grid at its cheapest). **NanoVDB**: a `ReadAccessor` on a NanoVDB "
          "level set of the same distances, normal from 3 forward differences.\n")
    print("| query | order | ns/query | vs raw array | vs NanoVDB |")
    print("|---|---|---:|---:|---:|")
    rows = [(k, v) for k, v in m.items() if k.startswith("BM_Sample/")]
    for name, (ns, label) in sorted(rows, key=lambda kv: kv[0]):
        order = int(name.split("/")[3])
        vs_nano = "%.2f" % (ns / nano[order]) if nano[order] else "n/a"
        parts = label.split()
        print("| %s %s | %s | %.1f | %.2f | %s |" % (parts[0], parts[1], parts[2], ns, ns / raw[order], vs_nano))
    for k in (0, 1):
        print("| raw array | %s | %.1f | 1.00 | %s |" % (("coherent", "random")[k], raw[k],
              "%.2f" % (raw[k] / nano[k]) if nano[k] else "n/a"))
        if nano[k]:
            print("| NanoVDB | %s | %.1f | %.2f | 1.00 |" % (("coherent", "random")[k], nano[k], nano[k] / raw[k]))
    goal_ns = 5.0
    got = m["BM_Sample/1/0/0"][0]
    print("\n**Goal (issue #2): bricked nearest, coherent points, at most %.0f ns per query. Measured: %.1f ns, %s.**"
          % (goal_ns, got, "reached" if got <= goal_ns else "not reached"))
    if got > goal_ns:
        print("The scalar query needs about 100 instructions per point (grid check, two dependent loads, range and "
              "octahedral decode, plane refinement; counted with callgrind), so the way to the goal is SIMD across "
              "points, not further scalar tuning.")


if __name__ == "__main__":
    main(sys.argv[1])
