#!/bin/sh
# same_swarm_every_set.sh DNGBAKE SWARM_HASH MESH WORK_DIR
# Bakes MESH (a real one: sharp edges and thin parts send particles down every path of the step) and
# steps the same swarms through it with the scalar path and with each SIMD set this machine has; every
# set must give the scalar path's hash, bit for bit. Two swarms: swarm_hash's default one (fast moves
# that spread out) and Table 1's load (respawned near the surface, slower), whose walks reach the end's
# proof in later cells more often. Table 1's load again as an array of structs (strided spans, which
# AVX-512 gathers and scatters) must give the arrays' hash. swarm_hash exits 3 for a set the machine
# lacks; any other failure fails the test.
set -e
bake="$1" swarm="$2" mesh="$3" work="$4"
mkdir -p "$work"
field="$work/field.dng"
"$bake" -q "$mesh" -o "$field" --resolution 64 --no-lift
compared=0
table1="--lifetime 8 --near 0.1 --speed 0.6"
arrays_hash=""
for load in "" "$table1" "$table1 --structs"; do
  # shellcheck disable=SC2086 # $load is a list of options
  out=$("$swarm" "$field" --particles 20000 --steps 12 $load --isa scalar) || { echo "the scalar run failed"; exit 1; }
  reference=$(echo "$out" | cut -d' ' -f1)
  [ "$load" = "$table1" ] && arrays_hash="$reference"
  if [ "$load" = "$table1 --structs" ] && [ "$reference" != "$arrays_hash" ]; then
    echo "structs: $reference differs from arrays: $arrays_hash"; exit 1
  fi
  for set in sse4.1 avx2 avx512 neon; do
    status=0
    # shellcheck disable=SC2086
    out=$("$swarm" "$field" --particles 20000 --steps 12 $load --isa "$set" 2>"$work/stderr.txt") || status=$?
    [ "$status" -eq 3 ] && continue # not on this machine
    [ "$status" -eq 0 ] || { echo "$set: swarm_hash failed (exit $status): $(cat "$work/stderr.txt")"; exit 1; }
    got=$(echo "$out" | cut -d' ' -f1)
    echo "${load:-default swarm}: $set: $got (scalar: $reference)"
    [ "$got" = "$reference" ] || { echo "$set differs from the scalar path"; exit 1; }
    compared=$((compared + 1))
  done
done
[ "$compared" -gt 0 ] || echo "no SIMD set on this machine: nothing to compare"
