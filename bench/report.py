"""Turns Google Benchmark JSON (with repetitions) into docs/PERFORMANCE.md.

DNG_REPORT_NAME, when set (bench/run.sh's second argument), makes the report one of another CPU's,
docs/PERFORMANCE_<name>.md, whose plot is docs/images/table1_sweep_<name>.png. Without it the report is
the run of record and links to the other CPUs' reports found beside it."""
import glob
import json
import os
import statistics
import sys

REPORT_NAME = os.environ.get("DNG_REPORT_NAME", "")
PLOT = "images/table1_sweep%s.png" % ("_" + REPORT_NAME if REPORT_NAME else "")
DOCS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "docs")


def medians(path, counter, scale=1e9):
    """Median of `counter` times `scale` (by default: seconds per item to ns), and the label, per benchmark."""
    with open(path) as f:
        data = json.load(f)
    out = {}
    for b in data["benchmarks"]:
        if b.get("aggregate_name") == "median":
            out[b["run_name"]] = (b[counter] * scale, b.get("label", ""))
    return data["context"], out


def repetitions(path):
    """How many repetitions each benchmark of the file ran (bench/run.sh passes one count per program)."""
    with open(path) as f:
        data = json.load(f)
    return max(b.get("repetitions", 1) for b in data["benchmarks"])


def spreads(path, counter):
    """The coefficient of variation of `counter` across repetitions, per benchmark."""
    with open(path) as f:
        data = json.load(f)
    return {b["run_name"]: b[counter] for b in data["benchmarks"] if b.get("aggregate_name") == "cv"}


def step_section(path):
    context, m = medians(path, "per_particle")
    base = m["BM_Step/2/0/0/real_time"][0]
    print("\n## Particle steps (bench/particle_step_bench.cpp)\n")
    print("1,048,576 particles within 2 voxels of the same sphere, random directions, up to 1 voxel per step, in "
          "random order (as an emitter produces them). One step = `applyGravity` + `stepParticles`; every iteration "
          "restarts from the same particle state. Baseline: the same step with no body. Each step runs with the "
          "best SIMD kernels of this CPU (`dng/instruction_set.h`) and again with the scalar reference path, whose "
          "results are bit for bit the same.\n")
    print("| body | responses | path | ns/particle | vs no collision | SIMD speed-up |")
    print("|---|---|---|---:|---:|---:|")
    for name, (ns, label) in sorted(m.items()):
        parts = label.split(" ", 1)
        body, responses = (parts[0], parts[1]) if len(parts) == 2 and parts[0] in ("dense", "bricked") else ("none", label)
        scalar = name.startswith("BM_StepScalar/")
        simd = m.get(name.replace("BM_StepScalar/", "BM_Step/"), (None,))[0] if scalar else None
        print("| %s | %s | %s | %.1f | %.2f | %s |" % (body, responses, "scalar" if scalar else "SIMD", ns, ns / base,
                                                  "%.2fx" % (ns / simd) if simd else ""))
    got = m["BM_Step/1/2/0/real_time"][0] / base
    sorted_gain = m["BM_Step/1/2/0/real_time"][0] / m["BM_Step/1/2/1/real_time"][0]
    swept = m["BM_Step/1/3/0/real_time"][0] / m["BM_Step/1/2/0/real_time"][0]
    print("\nKeeping particles sorted by voxel makes the bricked impact+drag+flow step %.2fx faster." % sorted_gain)
    print("\n**Goal: a swept step at most 2x the non-swept one. Measured: %.2fx (bricked impact+drag+flow), %s.**"
          % (swept, "reached" if swept <= 2.0 else "not reached"))
    print("\n**Goal: collision overhead at most 1.3x the no-collision step. Measured: %.1fx for bricked "
          "impact+drag+flow, %s.**" % (got, "reached" if got <= 1.3 else "not reached"))
    if got > 1.3:
        print("The no-collision step here is only gravity plus integration, a streaming loop bound by memory "
              "bandwidth; each collision step adds at least two field lookups in random order (the response's "
              "and the walk's proof of the end point: cache misses, see the random-order query rows above) plus "
              "the responses. The paper's 1.44x was measured against whole frames of a minimal particle system, "
              "not against a bare integration loop.")


def bake_section(path):
    with open(path) as f:
        data = json.load(f)
    ms = {}
    for b in data["benchmarks"]:
        if b.get("aggregate_name") == "median":
            ms[b["run_name"].split("/iterations")[0]] = (b["real_time"], b.get("label", ""))
    print("\n## Baking (bench/bake_bench.cpp)\n")
    print("The Stanford bunny (`bunny00.off`, 75,408 triangles, from Debian's libcgal-demo): the whole bake (load, "
          "checks, distance, sign, normals, conservative planes and their checks, bricked encoding, write) against "
          "OpenVDB's `meshToLevelSet` alone at the same voxel size and band, on the same mesh, in one run. "
          "Resolution 512 runs twice (median of 2), the rest "
          "5 times.\n")
    print("| bake | ms (wall) | vs meshToLevelSet at the same resolution |")
    print("|---|---:|---:|")
    resolution = lambda name: name.rsplit("/", 1)[-1]  # the last argument of every bake benchmark
    baseline = {resolution(n): t for n, (t, _) in ms.items() if n.startswith("BM_MeshToLevelSet")}
    for name, (t, label) in sorted(ms.items(), key=lambda item: (int(resolution(item[0])), item[0])):
        print("| %s | %.0f | %.2f |" % (label, t, t / baseline[resolution(name)]))
    blur = ms["BM_Dngbake/0/128"][0]
    base = baseline["128"]
    print("\n**Goal (issue #4): bunny at 128 in at most 1.5 s wall on 2 cores and at most 2x meshToLevelSet. "
          "Measured (normal-blur, the default): %.2f s and %.2fx, %s.**"
          % (blur / 1000.0, blur / base, "reached" if blur <= 1500 and blur / base <= 2.0 else "not reached"))


def table1_rows(path, aggregate="median"):
    """Medians (or another aggregate, such as each row's fastest repetition, "min") of
    bench/table1_bench.cpp: {(mesh, particles, case): {ns, label, crossings, judged, bytes, triangles}}."""
    with open(path) as f:
        data = json.load(f)
    rows = {}
    for b in data["benchmarks"]:
        if b.get("aggregate_name") != aggregate:
            continue
        _, mesh, particles, case = b["run_name"].split("/")[:4]
        rows[(mesh, int(particles), case)] = {
            "ns": b["per_particle"] * 1e9, "label": b.get("label", case), "crossings": int(b["crossings"]),
            "judged": int(b["judged"]), "bytes": int(b["bytes"]), "triangles": int(b["triangles"])}
    return rows


def embree_best(rows, mesh, particles, avx2=False):
    """The fastest Embree variant of a row, on the default device or (avx2) the one limited to AVX2:
    (case, its row)."""
    embree = [(case, r) for (m, n, case), r in rows.items() if m == mesh and n == particles and
              case.startswith("embree") and case.endswith("_avx2") == avx2]
    return min(embree, key=lambda item: item[1]["ns"])


def megabytes(count):
    return "%.2f MB" % (count / 1e6) if count else "-"


def table1_plot_data(rows, sweep_n, meshes, out_path):
    """Columns for bench/table1_plot.gp: triangles, then ns/particle-step of each plotted method."""
    with open(out_path, "w") as f:
        f.write("# mesh triangles plain bricked_impact bricked_flow embree_best nanovdb_nearest nanovdb_trilinear "
                "bricked_exact_flow (NaN: not run)\n")
        for mesh in meshes:
            r = lambda case: rows[(mesh, sweep_n, case)]["ns"] if (mesh, sweep_n, case) in rows else float("nan")
            f.write("%s %d %.3f %.3f %.3f %.3f %.3f %.3f %.3f\n" % (
                mesh, rows[(mesh, sweep_n, "plain")]["triangles"], r("plain"), r("dngrid_bricked_impact"),
                r("dngrid_bricked_flow"), embree_best(rows, mesh, sweep_n)[1]["ns"], r("nanovdb_nearest"),
                r("nanovdb_trilinear"), r("dngrid_bricked_exact_flow")))


def spread_from_median(values):
    """The smallest and largest value, and the largest relative distance of any from their median (of an
    even count, the mean of the middle two)."""
    median = statistics.median(values)
    return min(values), max(values), max(abs(x / median - 1.0) for x in values)


# Table 1's "Where the time goes": measured on scratch builds (profiles, counters, A/B runs), not
# by this run, so it is prose that changes only when someone measures again.
TIME_BREAKDOWN = [
    "**The two samples.** About 85% of the step's time is the lanes' own work: each particle's response "
    "sample (brick-top entry, then pool word and shading normal) and the sample at the end of its move that "
    "proves the move clear with two balls. The first ball alone proves almost no move here (it must leave 3 "
    "voxels of room, and these particles stay within 2), so nearly every particle takes both samples.",
    "**Bound by instructions and chains of gathers, not by cache misses.** On the AMD EPYC the profiler puts "
    "most of its samples just after those gathers (an AVX-512 gather takes about 9 ns from issue to result "
    "there, and three of the four depend on another). Yet plain loads in their place, four registers per "
    "operation instead of two, a smaller field and particles in spatial order all measured no faster, and "
    "prefetching the pool words and shading normals of the chunk one, two or four chunks ahead measured "
    "slower (18.0 ns per particle-step without, 19.5 to 19.9 with: the fastest timings of 3 runs of each, in "
    "turn). The evidence points to the instruction count (no hardware counters here to prove it): about 220 "
    "per particle-step with the AVX2 kernels (callgrind on bench/swarm_hash's Table 1-like load; valgrind "
    "cannot run AVX-512), spread over many small parts, the largest the brick lookups at about a fifth.",
    "**On an Intel Xeon** (perf with line information, the same swarm) about half of the step's time is in "
    "the samples' nearest-voxel lookups (brick-top entry, pool word, shading normal and the octahedral "
    "decodes), over a quarter of that just after the pool-word gathers. Taking each chunk's response samples "
    "one chunk ahead, so that two chunks' gathers overlap, gained about 2% with the AVX-512 kernels and 7% "
    "with the AVX2 ones (docs/RUNTIME.md, \"SIMD\"). Prefetching the pool words and shading entries of the "
    "chunk two or four ahead measured slower (2% and 7%), one register per operation slower (23.5 ns against "
    "19.3), four no faster (19.9 against 19.4), a normalization without the square root and division no "
    "faster, and the step costs the same from 4,000 to 400,000 particles (bench/swarm_hash, medians of 3 to "
    "6 runs in turn).",
    "**The particles the balls leave.** About 6% need the walk to go cell by cell (they are set aside and "
    "walked a register at a time) and 0.26% are handed to the scalar walk. About half of those stop at a "
    "plane during the move (a bounce and a slide); most of the rest are spawn points the planes cannot prove "
    "outside, which never move and are handed over every step (`Body::provesOutside` names such points; this "
    "emitter keeps them, as one that does not ask would). In a profile (perf, cpu-clock) the scalar walk "
    "takes about 6% of the step's time and the lanes' second-bound lookups, one lane at a time, about 4%. "
    "Pairs of second planes (beside concave creases) are stepped in lanes; handed over, they had been about "
    "60% of the scalar walks, when 0.7% of particle-steps were handed over.",
    "**Why detailed meshes cost more.** On the sweep's detailed meshes (below) 2-4% of particle-steps are "
    "handed over (the cow 2.2%, dragon_res4 3.7%), most of them such blocked particles, and the scalar walks "
    "take up to about 40% of the time. On dragon_res4 a third of their cycles go to spawn points never "
    "proven outside, and the 26-sample neighbour bound is about a fifth of the step; a swarm of nothing but "
    "blocked points cost about 320 ns per particle-step there, and 190 since the lanes take the bound at a "
    "walk's start and hand a blocked stop to the scalar code without its walk. That is why those meshes cost "
    "more than fandisk, and why the sweep's column of spawns the field proves costs less. On bench/swarm_hash's "
    "Table 1-like load about two thirds of dragon_res4's handed-over walks reach a cell whose planes prove "
    "nothing, at the start or part-way; taking those neighbour bounds in lanes halved the handovers but cost "
    "more than it saved (docs/RUNTIME.md, \"Tried on the single-body step and not kept\").",
    "**From spawns the field proves, the handovers still make the difference** (callgrind, AVX2 kernels, "
    "bench/swarm_hash at 20,000 particles and 60 steps of Table 1's load): on dragon_res4 0.86% of "
    "particle-steps are handed over, against 0.16% on fandisk, and each costs about 6,500 instructions "
    "(about 1.3 walks, each sampling about 5 cells and taking about 1.3 neighbour bounds of 26 samples), "
    "against about 215 for a particle-step the lanes settle. The step takes 261 instructions per "
    "particle-step there against 217 on fandisk, a fifth more, nearly all of it the handovers.",
    "**The dragons have no second bounds.** None of the sweep's three dragons is a clean solid (the "
    "decimated ones have non-manifold edges, the full scan 4,270 boundary edges in 151 parts), so dngbake "
    "writes them no second bounds (PLN2, docs/BAKING.md), which it writes for fandisk, the bunny and the "
    "cow. Baked without them, Table 1's swarm costs 15% more instructions on fandisk (45.2 to 51.9 million) "
    "and 13% more on the cow (66.1 to 74.6 million; callgrind, AVX2 kernels, 20,000 particles, 10 steps, "
    "no crossing in the 20,000 segments judged either way). Part of what the dragons cost more is that, not "
    "their triangle count.",
    "**Against the peers.** What Embree pays for a short segment near a 12,946-triangle mesh is a shallow "
    "BVH descent; what the field pays is fixed per sample.",
]


def print_time_breakdown():
    print("\n### Where the time goes\n")
    if REPORT_NAME:
        # The list below was measured on the run of record's machines, whatever CPU this report is of.
        print("The profiles and A/B runs behind the run of record's list ([PERFORMANCE.md](PERFORMANCE.md), "
              "\"Where the time goes\") were taken on its machines, not on this one. What was measured on a CPU "
              "without AVX-512 is in docs/RUNTIME.md, \"SIMD on CPUs without AVX-512\".")
        return
    print("Not part of this run: counters, profiles and A/B runs of scratch builds on this table's swarm "
          "(fandisk unless said).\n")
    for point in TIME_BREAKDOWN:
        print("- " + point)


def table1_section(path, table_mesh="fandisk"):
    rows = table1_rows(path)
    counts = sorted({n for (m, n, _) in rows if m == table_mesh})
    order = ["plain", "dngrid_nobody"] + ["dngrid_%s_%s" % (e, r) for e in ("dense", "bricked")
                                          for r in ("impact", "flow", "flow_swept")] + \
        ["dngrid_bricked_exact_flow", "dngrid_bricked_flow_avx2", "dngrid_bricked_flow_proven"] + \
        ["embree_rtcIntersect%d" % w for w in (1, 4, 8, 16)] + ["nanovdb_nearest", "nanovdb_trilinear"] + \
        ["embree_rtcIntersect%d_avx2" % w for w in (1, 4, 8, 16)]
    order = [c for c in order if (table_mesh, counts[0], c) in rows]
    first = rows[(table_mesh, counts[0], "plain")]
    print("\n## Table 1, redone (bench/table1_bench.cpp)\n")
    print("The paper's Table 1 measured the cost per particle of colliding with a 12,000-triangle object while all "
          "particles stay close to it. Here: `%s.off` (%s triangles), %s particles, every method on one thread in "
          "the same loop: a fixed respawn cycle (each particle lives %s steps, then restarts from its spawn state "
          "0.1-2 voxels outside the surface with up to 1 voxel per step in a random direction; 1/8 of the swarm "
          "respawns each step, so no particle gets far), gravity, then the method's step; dt = 1/60 s, one thread, "
          "particles in random order. The same response rule for every method: impact (paper §3.4) with "
          "beta 0.5, collision distance 0.1 voxel for the field methods; drag and flow (§3.5-3.6) only where "
          "the row says so. Fields: `dngbake`'s defaults at resolution 128 (normal-blur, band 4 voxels), baked in "
          "process; the level set is OpenVDB's `meshToLevelSet` on the same lattice, voxel size and band, "
          "converted to NanoVDB. Times are the stepping thread's CPU time (the machine is shared: time spent descheduled "
          "is not the method's), medians of %d repetitions run in random order among all the rows.\n" % (table_mesh, format(first["triangles"], ","),
                                         " and ".join(format(n, ",") for n in counts), "8", repetitions(path)))
    print("- **no collision**: respawn, gravity and `p += v dt`: the baseline every ratio divides by. The peers' own "
          "code (this loop, the NanoVDB steppers, the Embree callers) is built with `-march=native "
          "-fno-math-errno`, as a release build for this machine would be; dngrid's runtime picks its SIMD "
          "kernels at run time.")
    print("- **dngrid**: `dng::stepParticles` with one body (responses, then the walk that keeps particles out of "
          "the surface); *no body*: the same call with none.")
    # The bench adds the AVX2 rows only where the best kernels are AVX-512.
    avx512 = any(case.endswith("_avx2") for (m, k, case) in rows if m == table_mesh)
    print("- **Embree**: each step's segment `p -> p + v dt` cast at the triangles (default scene flags, high "
          "build quality: a static mesh; denormals flushed to zero, as Embree asks, for every method), one ray at "
          "a time (`rtcIntersect1`) or in packets of 4, 8 and 16 rays; on a hit the particle stops 0.001 voxel in "
          "front of the face and its velocity reflects with the impact rule. Embree picks its kernels at run time "
          "too" + ("" if not avx512 else ", AVX-512 here; the *AVX2 device* rows run the same on a device limited "
                   "to AVX2 (`max_isa=avx2`), the peer of dngrid's AVX2 row") +
          ". *Embree best* is the fastest variant on the default device.")
    print("- **NanoVDB**: distance at the particle and a normal from the gradient (central differences of the "
          "nearest voxel's 6 neighbours, or the trilinear field's gradient), the impact rule, `p += v dt`.\n")
    print("*Crossings*: before the timed runs, a copy of the warmed-up simulation they start from is stepped "
          "untimed and every step's segment, from before to after the method's move, is tested against the "
          "original triangles with Embree; a segment that meets any triangle counts. *Memory*: the mapped `.dng`, "
          "baked with `--no-lift` (the step "
          "never reads the LIFT section, which adds about a third for accurate queries; the normal-blur bakes "
          "carry their SHAD section, which the responses read, and the bricked bakes of clean solids their second "
          "bounds, PLN2, which the walk reads beside edges: dense files and the dragons below, none of them a "
          "clean solid, have none); Embree's vertex, index and BVH allocations as its memory-monitor callback "
          "reported them; the NanoVDB grid buffer. Particles (24 bytes each) come on top for every method.\n")
    header = "| method |" + "".join(" ns/particle-step (%s) | vs no collision | vs Embree best |" % format(n, ",")
                                     for n in counts) + " crossings / segments judged | memory |"
    print(header)
    print("|---|" + "---:|---:|---:|" * len(counts) + "---:|---:|")
    for case in order:
        cells = []
        for n in counts:
            r, base, best = rows[(table_mesh, n, case)], rows[(table_mesh, n, "plain")], embree_best(rows, table_mesh, n)
            # Embree ran from the mesh's own spawns only: no ratio for a row from other spawns.
            vs_best = "-" if case.endswith("_proven") else "%.2f" % (r["ns"] / best[1]["ns"])
            cells.append("%.1f | %.1f | %s" % (r["ns"], r["ns"] / base["ns"], vs_best))
        judged = " / ".join("%s of %s" % (format(rows[(table_mesh, n, case)]["crossings"], ","),
                                         format(rows[(table_mesh, n, case)]["judged"], ",")) for n in counts)
        label = rows[(table_mesh, counts[0], case)]["label"]
        print("| %s | %s | %s | %s |" % (label, " | ".join(cells), judged,
                                        megabytes(rows[(table_mesh, counts[0], case)]["bytes"])))

    # The goals, at the table's smaller swarm.
    n = counts[0]
    r = lambda case: rows[(table_mesh, n, case)]["ns"]
    best_case, best = embree_best(rows, table_mesh, n)
    speedup = best["ns"] / r("dngrid_bricked_flow")
    vs_plain = r("dngrid_bricked_flow") / r("plain")
    swept = r("dngrid_bricked_flow_swept") / r("dngrid_bricked_flow")
    verdict = lambda ok: "reached" if ok else "not reached"
    print("\nEmbree's best variant here is %s." % best["label"])
    print("\n**Goals (%s, %s particles):**\n" % (table_mesh, format(n, ",")))
    print("- bricked impact+drag+flow at least 3x faster than Embree's best: measured %.2fx, %s."
          % (speedup, verdict(speedup >= 3.0)))
    print("- bricked impact+drag+flow at most 8x the no-collision loop: measured %.1fx, %s."
          % (vs_plain, verdict(vs_plain <= 8.0)))
    print("- swept at most 2x the same step not swept (bricked impact+drag+flow): measured %.2fx, %s."
          % (swept, verdict(swept <= 2.0)))
    fastest = table1_rows(path, "min")
    if (table_mesh, n, "dngrid_bricked_flow") in fastest:
        f = lambda case: fastest[(table_mesh, n, case)]["ns"]
        f_best = embree_best(fastest, table_mesh, n)[1]["ns"]
        print("\nThe medians are the figures of record. From each row's fastest repetition instead, the run's "
              "least disturbed one (other tenants of this shared machine slow dngrid's SIMD kernels more than "
              "Embree's traversal): bricked impact+drag+flow %.1f ns against Embree's best %.1f, %.2fx faster, "
              "and %.1fx the no-collision loop." % (f("dngrid_bricked_flow"), f_best, f_best / f("dngrid_bricked_flow"),
                                                     f("dngrid_bricked_flow") / f("plain")))
    if (table_mesh, n, "dngrid_bricked_exact_flow") in rows:
        exact = r("dngrid_bricked_exact_flow")
        print("\nThe same step through an exact-mode bake (`dngbake --mode exact`): %.1f ns, %.2fx faster than "
              "Embree's best and %.1fx the no-collision loop. Both bakes walk the same planes (docs/FORMAT.md §5.4); "
              "the exact one has no SHAD section, so each response takes its normal from the voxel word it has "
              "already loaded instead of gathering and decoding a shading normal, and more of its tiles are plane "
              "tiles, a blurred tile becoming one only when its shading normals fit the plane too (fandisk at "
              "resolution 128, `dngdump`: 177 plane tiles against 87). The blurred modes give smoother normals for "
              "drag and flow (docs/BAKING.md)." % (exact, best["ns"] / exact, exact / r("plain")))
    if (table_mesh, n, "dngrid_bricked_flow_avx2") in rows:
        avx2 = r("dngrid_bricked_flow_avx2")
        print("\nThe rows above run the best kernels this CPU has, AVX-512 (32 particles per chunk, two "
              "registers of 16: docs/RUNTIME.md, \"SIMD\"). The same bricked impact+drag+flow step with the AVX2 "
              "kernels, what a CPU without AVX-512 runs: %.1f ns, %.2fx Embree's best (which itself runs its AVX-512 "
              "kernels here)." % (avx2, best["ns"] / avx2), end="")
        if any(case.endswith("_avx2") and case.startswith("embree") for (m, k, case) in rows if m == table_mesh):
            avx2_best = embree_best(rows, table_mesh, n, avx2=True)[1]
            print(" Against Embree on a device limited to AVX2 as well (its `max_isa=avx2`, the last rows: "
                  "both as such a CPU runs them), whose best variant is %s at %.1f ns: %.2fx faster." % (
                      avx2_best["label"].split(",")[0], avx2_best["ns"], avx2_best["ns"] / avx2), end="")
        print()
    if (table_mesh, n, "dngrid_bricked_flow_proven") in rows:
        proven = r("dngrid_bricked_flow_proven")
        print("\n*Spawns the field proves*: the same step from a swarm whose spawn points the field also proves "
              "outside (`Body::provesOutside`, as an emitter that asks spawns; the other rows keep every point the "
              "mesh alone chose, as an emitter that does not ask would): %.1f ns, %.1fx the no-collision loop (Embree "
              "and NanoVDB were not run from these spawns, so no ratio to them is given). A point just outside a "
              "detail the field cannot resolve is blocked where it spawns, and its walk runs every step it lives "
              "(docs/RUNTIME.md, \"Limits\"); on fandisk there are few." % (proven, proven / r("plain")))
    print_time_breakdown()

    # The sweep: every mesh at the sweep's swarm size (the table's mesh included when it ran at that size).
    sweep_n = min(n for (m, n, _) in rows if m != table_mesh) if any(m != table_mesh for (m, _, _) in rows) else n
    meshes = sorted({m for (m, k, _) in rows if k == sweep_n}, key=lambda m: rows[(m, sweep_n, "plain")]["triangles"])
    print("\n### Cost against triangle count\n")
    print("The same loop, %s particles, on %d meshes: `cow.off` (libcgal-demo), `fandisk.off`, `bunny00.off` and "
          "the Stanford dragon at three of its resolutions (`dragon_res4`, `dragon_res2`, `dragon`: the same shape "
          "from 11k to 871k triangles; bench/fetch_table1_meshes.sh fetches them). Each field is baked at "
          "resolution 128, so its voxel follows the mesh's size, and speeds and distances are in voxels, so every "
          "mesh sees the same motion. ns per particle-step, medians; Embree best is the fastest of its four "
          "variants on that mesh. The two decimated dragons are not clean solids (the scan's decimation left 803 "
          "and 2,534 non-manifold edges, and `dragon_res2` is 7 overlapping parts): there the field's winding-number "
          "sign and the judge's triangles can disagree about what is inside, and a crossing can come from the "
          "mesh rather than the method. The full scan is not closed either (4,270 boundary edges in 151 parts), so "
          "none of the three dragons gets the second bounds the other meshes have (\"Where the time goes\").\n"
          % (format(sweep_n, ","), len(meshes)))
    proven = all((m, sweep_n, "dngrid_bricked_flow_proven") in rows for m in meshes)
    print("| mesh | triangles | no collision | dngrid bricked, impact | dngrid bricked, impact+drag+flow | " +
          ("dngrid i+d+f, spawns the field proves | " if proven else "") +
          "Embree best | NanoVDB nearest | NanoVDB trilinear | Embree best / dngrid i+d+f | crossings: dngrid i+d+f, "
          "Embree best, NanoVDB nearest |")
    print("|---|---:|---:|---:|---:|" + ("---:|" if proven else "") + "---:|---:|---:|---:|---:|")
    for mesh in meshes:
        g = lambda case: rows[(mesh, sweep_n, case)]
        best_case, best = embree_best(rows, mesh, sweep_n)
        print("| %s | %s | %.1f | %.1f | %.1f |%s %.1f (%s) | %.1f | %.1f | %.2f | %d, %d, %s of %s |" % (
            mesh, format(g("plain")["triangles"], ","), g("plain")["ns"], g("dngrid_bricked_impact")["ns"],
            g("dngrid_bricked_flow")["ns"],
            " %.1f (%d) |" % (g("dngrid_bricked_flow_proven")["ns"], g("dngrid_bricked_flow_proven")["crossings"])
            if proven else "", best["ns"], best_case.split("_")[1], g("nanovdb_nearest")["ns"],
            g("nanovdb_trilinear")["ns"], best["ns"] / g("dngrid_bricked_flow")["ns"],
            g("dngrid_bricked_flow")["crossings"], best["crossings"], format(g("nanovdb_nearest")["crossings"], ","),
            format(g("plain")["judged"], ",")))
    spread = lambda case: spread_from_median([rows[(m, sweep_n, case)]["ns"] for m in meshes])
    low, high, worst = spread("dngrid_bricked_flow")
    print("\n![ns per particle-step against triangle count](%s)\n" % PLOT)
    print("**Goal: the bricked impact+drag+flow step's cost flat within +-15%% from %s to %s triangles. Measured: "
          "%.1f to %.1f ns, at most %.0f%% from their median, %s.**" % (
              format(rows[(meshes[0], sweep_n, "plain")]["triangles"], ","),
              format(rows[(meshes[-1], sweep_n, "plain")]["triangles"], ","), low, high, 100 * worst,
              verdict(worst <= 0.15)))
    if proven:
        low, high, worst = spread("dngrid_bricked_flow_proven")
        print("\nFrom spawn points the field proves outside (the column beside it; in brackets its crossings of "
              "as many segments judged) the same step takes %.1f to %.1f ns, at most %.0f%% from their median "
              "(the peers were not run from these spawns, so the table compares them with the other columns' "
              "spawns only). The difference is the spawn points the field cannot prove outside: each is blocked "
              "where it spawns, and every step it lives the lanes take its neighbour bound and hand the stop to the "
              "scalar code, which settles it without walking." % (low, high, 100 * worst))
    if all((m, sweep_n, "dngrid_bricked_exact_flow") in rows for m in meshes):
        low, high, worst = spread("dngrid_bricked_exact_flow")
        ratios = [embree_best(rows, m, sweep_n)[1]["ns"] / rows[(m, sweep_n, "dngrid_bricked_exact_flow")]["ns"]
                  for m in meshes]
        print("\nThrough exact-mode bakes the same step takes %.1f to %.1f ns, at most %.0f%% from their median, "
              "and runs %.2fx to %.2fx as fast as Embree's best on the same mesh." % (
                  low, high, 100 * worst, min(ratios), max(ratios)))
    # One shape at several resolutions (name, name_res2, ...) isolates the triangle count from the shape.
    for full in meshes:
        coarse = [m for m in meshes if m.startswith(full + "_res")]
        if not coarse:
            continue
        low = min(coarse, key=lambda m: rows[(m, sweep_n, "plain")]["triangles"])
        change = lambda pick: pick(full)["ns"] / pick(low)["ns"] - 1.0
        flow = lambda m: rows[(m, sweep_n, "dngrid_bricked_flow")]
        best = lambda m: embree_best(rows, m, sweep_n)[1]
        print("\nThe same shape, %s: from %s to %s triangles the bricked impact+drag+flow step changes by %+.0f%%, "
              "Embree's best by %+.0f%%, NanoVDB nearest by %+.0f%%." % (
                  full, format(flow(low)["triangles"], ","), format(flow(full)["triangles"], ","),
                  100 * change(flow), 100 * change(best),
                  100 * change(lambda m: rows[(m, sweep_n, "nanovdb_nearest")])))
    table1_plot_data(rows, sweep_n, meshes, path.rsplit(".", 1)[0] + "_sweep.dat")


def bodies_section(path):
    with open(path) as f:
        data = json.load(f)
    extra = {b["run_name"]: b for b in data["benchmarks"] if b.get("aggregate_name") == "median"}
    rows = {int(name.split("/")[1]): (b["per_particle"] * 1e9, b.get("label", ""))
            for name, b in extra.items() if name.startswith("BM_Rain/")}
    print("\n## Many bodies (bench/many_bodies_bench.cpp)\n")
    print("A city (bench/city_scene.h, paper Fig. 8): 1,000 box buildings sharing one box field, each with its own "
          "scale (4 to 8 wide, 8 to 16 tall) and turn, on a 40 x 25 lattice 20 units apart (no two buildings' grids overlap), on a ground slab (a "
          "second field); 100,000 raindrops anywhere up to 20 units high, falling at about 12 units/s, in random "
          "order. One step = `applyGravity` + `BodyIndex::rebuild` (the broadphase rows: an engine calls it every "
          "frame; the buildings stand still, so each call after the first only compares them) + `stepParticles`; every iteration restarts from the same state. Medians of the rows' %d "
          "repetitions, interleaved; run of %s.\n"
          % (repetitions(path), data["context"].get("date", "?")))
    print("| bodies | ns/particle | vs its 1-body baseline |")
    print("|---|---:|---:|")
    base = {0: rows[0][0], 1: rows[0][0], 2: rows[0][0], 3: rows[3][0], 4: rows[3][0], 5: rows[5][0], 6: rows[5][0]}
    for k in sorted(rows):
        ns, label = rows[k]
        print("| %s | %.1f | %.2f |" % (label, ns, ns / base[k]))
    rebuild = extra.get("BM_Rebuild/1/real_time")
    tenth = extra.get("BM_Rebuild/10/real_time")
    unchanged = extra.get("BM_Rebuild/0/real_time")
    call = extra.get("BM_CallOverhead/real_time")
    if rebuild and tenth and unchanged:
        print("\nRebuilding the index of the 1,001 bodies: %.0f us when every body has changed velocity (%s), %.0f us "
              "when a tenth of them have; %.1f us when they are as the last rebuild left them, as here, where the "
              "buildings stand still and every step's rebuild only compares them. Per call with the index, besides "
              "its particles (argument and staleness checks, O(bodies)): %.1f us."
              % (rebuild["real_time"], rebuild.get("label", ""), tenth["real_time"], unchanged["real_time"],
                 call["real_time"] if call else float("nan")))
    literal = rows[1][0] / rows[0][0]
    same_work = rows[4][0] / rows[3][0]
    print("\n**Goal (many bodies): 1,000 bodies at most 2x the per-particle cost of 1 body. Measured: %.2fx for the "
          "1,000 buildings against building 0 alone with the same field work per drop (%s); %.2fx for the city with "
          "its ground against the ground alone with the same raindrops (%s).** Folded onto building 0 each drop "
          "samples the same local field as in the city, so that ratio is what many bodies cost: the grid lookups, "
          "and the bodies' data no longer in the first-level cache (drops in lattice order: %.2fx). Against the "
          "ground alone a drop among the buildings also samples a building about a quarter of the time. Without the "
          "broadphase the city costs %.0fx the ground alone. Every row runs the SIMD kernels; through the index "
          "each lane of a chunk lists its own bodies, testing each body of its cell by the coarse copy of its grown "
          "box that the cell keeps (docs/RUNTIME.md, \"Many bodies in lanes\"). A chunk where at most half the lanes meet a body "
          "moves the others at once and queues those with their lists; once a chunk's worth is queued, gathered "
          "from several chunks, they are stepped together. A chunk steps its lanes' bodies slot by slot: in "
          "random order the lanes' different buildings (one field, one material, one kind noted by the index) run "
          "in one pass with each lane's body gathered; in lattice order a chunk's lanes mostly share their "
          "building. A profile of the random-order buildings (perf with line information, AVX-512 kernels) puts "
          "about a third of the time in listing each lane's bodies (the cells' coarse boxes gathered, two entries "
          "per gathered element, and tested 13%%, each cell's first and last entry 4%%, the bodies of the entries "
          "that met 3%%, lanes whose moves cross a cell wall, listed one at a time, 5%%), 12%% in making the "
          "slots (each lane's pose, box and "
          "band gathered, two floats per gathered element, 9%%; choosing the slots, in registers, 3%%: lane by "
          "lane it had taken 7%%), a fifth "
          "in the responses and the balls, 7%% in the set-aside walks, and the rest in loading, queueing and "
          "storing the chunks. The faster single-body kernels (AVX-512) make those shares, and the ratio, "
          "larger."
          % (same_work, "reached" if same_work <= 2.0 else "not reached", literal,
             "reached" if literal <= 2.0 else "not reached", rows[6][0] / rows[5][0], rows[2][0] / rows[0][0]))


def threads_section(path):
    _, m = medians(path, "per_particle")
    one, two = m["BM_Threads/1/real_time"][0], m["BM_Threads/2/real_time"][0]
    with open(path) as f:
        context = json.load(f)["context"]
    print("\n## Threads (bench/threads_bench.cpp)\n")
    print("The city's step (above, without the per-frame rebuild: the index is built once, untimed, and shared "
          "read-only): 1 thread on all 100,000 raindrops against 2 threads on the two halves. The threads are a "
          "minimal job system's workers, started once and spinning "
          "between frames, the calling thread taking the first half itself; each iteration steps 8 consecutive "
          "frames from the same start, so each half stays in its worker's cache as in a game (%d CPUs; "
          "medians of %d repetitions, interleaved; run of %s). "
          "On a machine whose cores other work shares, the second thread gets what is left of the second core.\n"
          % (context.get("num_cpus", 0), repetitions(path), context.get("date", "?")))
    _, cpu = medians(path, "cpu_ms_busiest_thread", scale=1.0)  # already milliseconds
    cpu_one, cpu_two = cpu["BM_Threads/1/real_time"][0], cpu["BM_Threads/2/real_time"][0]
    print("The last columns time the busiest thread's CPU alone, which time spent descheduled does not count.\n")
    print("| threads | ns/particle-step | speed-up | busiest thread's CPU ms per step | speed-up by CPU time |")
    print("|---|---:|---:|---:|---:|")
    print("| 1 | %.1f | 1.00 | %.2f | 1.00 |" % (one, cpu_one))
    print("| 2 | %.1f | %.2f | %.2f | %.2f |" % (two, one / two, cpu_two, cpu_one / cpu_two))
    print("\n**Goal (threads): 2 threads at least 1.8x as fast as 1. Measured: %.2fx, %s.**"
          % (one / two, "reached" if one / two >= 1.8 else "not reached"))
    cv = spreads(path, "real_time")
    print("\nThe repetitions' wall times varied by %.0f%% (1 thread) and %.0f%% (2 threads), coefficients of "
          "variation; on this shared machine the ratio moves by about as much from run to run."
          % (100 * cv["BM_Threads/1/real_time"], 100 * cv["BM_Threads/2/real_time"]))


def main(path, step_path=None, bake_path=None, table1_path=None, bodies_path=None, threads_path=None):
    context, m = medians(path, "per_query")
    raw = {0: m["BM_RawArray/0"][0], 1: m["BM_RawArray/1"][0]}
    nano = {k: m.get("BM_NanoVdb/%d" % k, (None,))[0] for k in (0, 1)}
    isa = context.get("instruction_set")
    print("# Performance%s\n" % (" on another CPU (%s)" % REPORT_NAME if REPORT_NAME else ""))
    print("Written by `bash setup.sh bench` (bench/run.sh%s); do not edit by hand. Medians of %d repetitions (Table 1, "
          "the many bodies and the threads: each section says how many), measured on %s (%s, %d CPUs, %s%s). "
          "Absolute times on shared machines drift by tens of percent between runs; the ratios to baselines "
          "measured in the same run are the figures to compare, on the same CPU model: between CPU makers they "
          "differ too.\n"
          % (" with the name `%s`" % REPORT_NAME if REPORT_NAME else "", repetitions(path),
             context.get("host_name", "?"), context.get("cpu_model", "CPU model not recorded"),
             context.get("num_cpus", 0), context.get("date", "?"),
             ", the runtime's %s kernels" % isa if isa else ""))
    others = sorted(os.path.basename(f) for f in glob.glob(os.path.join(DOCS, "PERFORMANCE_*.md")))
    if not REPORT_NAME and others:
        print("The same benchmarks on other CPUs, each report from one run there: %s.\n"
              % ", ".join("[%s](%s)" % (f, f) for f in others))
    print("## Field queries (bench/field_query_bench.cpp)\n")
    print("A 128^3 sphere field (radius 48 voxels, band 3 voxels); the same ~116k points within 2 voxels of the "
          "surface, in scan order (coherent) and shuffled (random), sampled with `View::sampleBatch`.\n")
    print("Baselines: **raw array**: the voxel's float4 from a bare array (bounds check, no refinement, no "
          "validation: the paper's plain normal grid at its cheapest). **NanoVDB**: a `ReadAccessor` on a NanoVDB "
          "level set of the same distances, normal from 3 forward differences.\n")
    print("Each query runs with the best SIMD kernels of this CPU and again with the scalar reference path, "
          "whose samples are bit for bit the same (last columns). The accurate and `+SHAD` rows read the same field "
          "written with LIFT and SHAD sections, as `dngbake` writes a normal-blur or potential bake (format 1.3: "
          "here the lifts are zero and the shading normals are the normals, so only the reads are added); the "
          "goal below is on the plain field, whose normals, like NanoVDB's, are the distance's own.\n")
    print("| query | order | ns/query | vs raw array | vs NanoVDB | scalar ns/query | SIMD speed-up |")
    print("|---|---|---:|---:|---:|---:|---:|")
    rows = [(k, v) for k, v in m.items() if k.startswith("BM_Sample/") and k.endswith("/0")]
    for name, (ns, label) in sorted(rows, key=lambda kv: kv[0]):
        order = int(name.split("/")[3])
        vs_nano = "%.2f" % (ns / nano[order]) if nano[order] else "n/a"
        scalar = m[name[:-1] + "1"][0]
        parts = label.split()
        print("| %s %s | %s | %.1f | %.2f | %s | %.1f | %.2fx |"
              % (parts[0], parts[1], parts[2], ns, ns / raw[order], vs_nano, scalar, scalar / ns))
    for k in (0, 1):
        print("| raw array | %s | %.1f | 1.00 | %s | | |" % (("coherent", "random")[k], raw[k],
              "%.2f" % (raw[k] / nano[k]) if nano[k] else "n/a"))
        if nano[k]:
            print("| NanoVDB | %s | %.1f | %.2f | 1.00 | | |" % (("coherent", "random")[k], nano[k], nano[k] / raw[k]))
    if nano[0] and nano[1]:
        coherent, random = m["BM_Sample/1/0/0/0"][0] / nano[0], m["BM_Sample/1/0/1/0"][0] / nano[1]
        print("\n**Goal: bricked nearest `sampleBatch` at most 0.4x NanoVDB on coherent points and 0.5x on random "
              "ones. Measured: %.2fx (%s) and %.2fx (%s).**"
              % (coherent, "reached" if coherent <= 0.4 else "not reached", random,
                 "reached" if random <= 0.5 else "not reached"))
    goal_ns = 5.0
    got = m["BM_Sample/1/0/0/0"][0]
    print("\n**Goal (issue #2): bricked nearest, coherent points, at most %.0f ns per query. Measured: %.1f ns, %s.**"
          % (goal_ns, got, "reached" if got <= goal_ns else "not reached"))
    print("The batch runs in SIMD lanes (32 points per chunk with AVX-512, 16 with AVX2); the nearest query takes "
          "two chunks of points at a time so that their chains of dependent gathers (brick-top entry, then pool "
          "word) overlap. Packed `Vec3f` points and the 20-byte `Sample`s are moved in and out of the lanes with "
          "lane permutes on AVX-512 and with shuffles within each register's 128-bit halves on AVX2 and SSE4.1. "
          "A transpose through the stack, lane by lane, had taken about 40% of the time on an Intel Xeon with "
          "AVX-512 (coherent bricked nearest 5.9 -> 3.2 ns per query with the permutes) and a quarter of the "
          "instructions with the AVX2 kernels (56 -> 43 per query with the shuffles, callgrind).")


    if step_path:
        step_section(step_path)
    if bodies_path:
        bodies_section(bodies_path)
    if threads_path:
        threads_section(threads_path)
    if bake_path:
        bake_section(bake_path)
    if table1_path:
        table1_section(table1_path)


if __name__ == "__main__":
    main(*sys.argv[1:])
