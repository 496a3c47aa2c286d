#!/usr/bin/env bash
# setup.sh: one entry point for installing, building, testing and running dngrid.
#
#   bash setup.sh test           install what is missing, build (Release), run the whole test suite
#   bash setup.sh demo           bake the Stanford bunny, check it, run particles, write pictures to out/
#                                (DNG_DEMO_BUILD=DIR: use that already-configured build tree instead)
#   bash setup.sh deps           only install the Debian packages the project needs
#   bash setup.sh clang          build (Release) and run the whole test suite with clang instead of GCC
#   bash setup.sh asan           build (clang) and test with AddressSanitizer + UndefinedBehaviorSanitizer
#   bash setup.sh tsan           build and test the runtime with ThreadSanitizer (no baker)
#   bash setup.sh determinism    bake one mesh with --threads 1 and --threads 2, compare the bytes
#   bash setup.sh runtime-only   build and test format + runtime with the baker and its libraries off
#   bash setup.sh aarch64        cross-build the runtime and its tests for 64-bit ARM, run them under qemu-user
#   bash setup.sh package        install (full and runtime-only) into temporary prefixes, build C and C++
#                                consumers against them, check libdngrid's exported symbols
#   bash setup.sh format-check   check clang-format on every source file
#   bash setup.sh bench [NAME]   build and run the benchmarks, write docs/PERFORMANCE.md (with NAME: another
#                                CPU's report, docs/PERFORMANCE_NAME.md, beside the run of record)
#   bash setup.sh leaks          run the full leak table (particles judged on the triangles), write docs/LEAKS.md
#   bash setup.sh fuzz [SECONDS] fuzz the loader (default 60 s), dngdump and the step (half that each), replay regressions
#   bash setup.sh fuzz-meshes [SECONDS]  fuzz mesh loading, open-ended (default 300 s)
#   bash setup.sh fuzz-scenes [SECONDS]  fuzz the glTF importer, open-ended (default 300 s)
#   bash setup.sh fuzz-assimp [SECONDS]  fuzz assimp's readers in process, open-ended (default 300 s)
#   bash setup.sh ccache-stats   print the compiler cache's hits and misses (DNG_CCACHE=ON builds)
#
# Environment: DNG_WERROR=ON turns warnings into errors (CI sets it). DNG_JOBS sets build parallelism.
# DNG_CCACHE=ON compiles through ccache (installed if missing), cached in build/ccache: build trees
# that compile the same sources with the same flags share their objects (CI sets it).
# Every command installs what it needs first; running it twice does no extra work.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
JOBS="${DNG_JOBS:-$(nproc 2>/dev/null || echo 2)}"
WERROR="${DNG_WERROR:-OFF}"
CCACHE="${DNG_CCACHE:-OFF}"

# Debian 12 packages. Build tools first, then the runtime's test libraries, then the baker's.
PACKAGES_BUILD=(cmake ninja-build g++ pkg-config clang-format bc)
PACKAGES_TEST=(libgtest-dev libgmock-dev libbenchmark-dev libxxhash-dev)
PACKAGES_BAKER=(libopenmesh-dev libembree-dev libopenvdb-dev libnanovdb-dev libboost-iostreams-dev libcli11-dev
                libtbb-dev libpng-dev nlohmann-json3-dev libxxhash-dev libtinygltf-dev libassimp-dev)

log() { printf 'setup.sh: %s\n' "$*" >&2; }

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@"; else
    log "need root to run: $*"; exit 1
  fi
}

install_packages() {
  local missing=()
  for pkg in "$@"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || missing+=("$pkg")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  log "installing ${missing[*]}"
  as_root env DEBIAN_FRONTEND=noninteractive apt-get update -qq
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

deps() { install_packages "${PACKAGES_BUILD[@]}" "${PACKAGES_TEST[@]}" "${PACKAGES_BAKER[@]}"; }

# With DNG_CCACHE=ON: the compiler launcher for every build tree configured from here on. Paths under the
# source tree are hashed relative to the build directory, so build/release and build/demo (the same
# depth) share the objects they compile alike.
ccache_dir() { echo "${CCACHE_DIR:-$ROOT/build/ccache}"; }
use_ccache() {
  [ "$CCACHE" = ON ] || return 0
  install_packages ccache
  export CCACHE_DIR="$(ccache_dir)" CCACHE_BASEDIR="$ROOT"
  export CMAKE_C_COMPILER_LAUNCHER=ccache CMAKE_CXX_COMPILER_LAUNCHER=ccache
}

# The cache's hits and misses so far (nothing when ccache is not installed or the cache is empty).
cmd_ccache_stats() { CCACHE_DIR="$(ccache_dir)" ccache --show-stats 2>/dev/null | grep -iE "hits|misses" || true; }

# configure_and_build <build-dir> [cmake args...]
configure_and_build() {
  local dir="$1"; shift
  use_ccache
  cmake -S "$ROOT" -B "$dir" -G Ninja -DDNG_WERROR="$WERROR" "$@" >/dev/null
  cmake --build "$dir" --parallel "$JOBS"
}

run_tests() { ctest --test-dir "$1" --output-on-failure --parallel "$JOBS" --timeout 600; }

cmd_test() {
  deps
  fetch_data # leak_test throws particles at the real meshes
  configure_and_build "$ROOT/build/release" -DCMAKE_BUILD_TYPE=Release -DDNG_BUILD_TESTS=ON -DDNG_BUILD_BENCH=ON
  run_tests "$ROOT/build/release"
}

# The same build and tests with Debian's clang instead of GCC: its warnings differ (with DNG_WERROR=ON
# they are errors), and the SIMD kernels must give the scalar code's bits whichever compiler built them.
cmd_clang() {
  deps
  install_packages clang
  fetch_data
  CC=clang CXX=clang++ configure_and_build "$ROOT/build/clang" -DCMAKE_BUILD_TYPE=Release -DDNG_BUILD_TESTS=ON \
    -DDNG_BUILD_BENCH=ON
  run_tests "$ROOT/build/clang"
}

# Built with clang: it compiles the instrumented build in about three quarters of GCC's time (CI must stay short).
cmd_asan() {
  deps
  install_packages clang
  fetch_data
  CC=clang CXX=clang++ configure_and_build "$ROOT/build/asan" -DCMAKE_BUILD_TYPE=ASan -DDNG_BUILD_TESTS=ON \
    -DDNG_BUILD_SAMPLES=OFF
  # A sanitizer build that silently lost its flags would pass everything: check the instrumentation.
  if ! grep -q " __asan_" <(nm "$ROOT/build/asan/tests/reject_test"); then
    log "the ASan build is not instrumented"; exit 1
  fi
  ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    run_tests "$ROOT/build/asan"
}

# The runtime's threaded tests (shared fields and bodies) under ThreadSanitizer. The baker is left out:
# TBB's own synchronisation is not visible to ThreadSanitizer in Debian's build and would be reported.
cmd_tsan() {
  install_packages "${PACKAGES_BUILD[@]}" libgtest-dev libgmock-dev
  configure_and_build "$ROOT/build/tsan" -DCMAKE_BUILD_TYPE=TSan -DDNG_BUILD_BAKER=OFF -DDNG_BUILD_TOOLS=OFF \
    -DDNG_BUILD_SAMPLES=OFF -DDNG_BUILD_BENCH=OFF -DDNG_BUILD_TESTS=ON
  if ! grep -q " __tsan_" <(nm "$ROOT/build/tsan/tests/particles_test"); then
    log "the TSan build is not instrumented"; exit 1
  fi
  TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1 run_tests "$ROOT/build/tsan"
}

# A torus as OBJ on stdout (no data download needed): rings x sides quads, split into triangles.
write_torus_obj() {
  awk -v rings=96 -v sides=48 'BEGIN {
    pi = 3.14159265358979
    for (i = 0; i < rings; i++) for (j = 0; j < sides; j++) {
      u = 2 * pi * i / rings; v = 2 * pi * j / sides
      printf "v %.6f %.6f %.6f\n", (1 + 0.35 * cos(v)) * cos(u), (1 + 0.35 * cos(v)) * sin(u), 0.35 * sin(v)
    }
    for (i = 0; i < rings; i++) for (j = 0; j < sides; j++) {
      a = i * sides + j + 1; b = ((i + 1) % rings) * sides + j + 1
      c = ((i + 1) % rings) * sides + (j + 1) % sides + 1; d = i * sides + (j + 1) % sides + 1
      printf "f %d %d %d\nf %d %d %d\n", a, b, c, a, c, d
    }
  }'
}

# The baker's promise that the output never depends on the thread count, checked on the real program.
cmd_determinism() {
  local bake="$ROOT/build/release/tools/dngbake" dir="$ROOT/build/determinism"
  [ -x "$bake" ] || { log "build first: bash setup.sh test"; exit 1; }
  mkdir -p "$dir"
  write_torus_obj > "$dir/torus.obj"
  for mode in normal-blur potential; do
    "$bake" "$dir/torus.obj" -o "$dir/one.dng" --mode "$mode" --resolution 160 --threads 1 --quiet
    "$bake" "$dir/torus.obj" -o "$dir/two.dng" --mode "$mode" --resolution 160 --threads 2 --quiet
    cmp "$dir/one.dng" "$dir/two.dng" || { log "$mode: --threads 1 and --threads 2 differ"; exit 1; }
  done
  log "determinism: --threads 1 and 2 give the same bytes"
}

# The runtime must not need any baker library: make CMake unable to find them, and make sure no
# format/ or runtime/ source includes their headers (which are installed on this machine).
cmd_runtime_only() {
  install_packages "${PACKAGES_BUILD[@]}" libgtest-dev libgmock-dev
  if grep -rnE '#include *[<"](openvdb|nanovdb|embree[34]?|OpenMesh|CLI|tbb|oneapi|assimp)/|tiny_gltf' "$ROOT/format" "$ROOT/runtime"; then
    log "format/ or runtime/ includes a baker library header"; exit 1
  fi
  configure_and_build "$ROOT/build/runtime-only" "${RUNTIME_ONLY_FLAGS[@]}"
  run_tests "$ROOT/build/runtime-only"
  check_embedding
}

# An engine that embeds dngrid with add_subdirectory gets format and runtime only, and keeps its own
# (here: empty) CMAKE_BUILD_TYPE. Configure-only: a few seconds.
check_embedding() {
  local parent="$ROOT/build/embed"
  mkdir -p "$parent"
  printf 'cmake_minimum_required(VERSION 3.25)\nproject(engine C CXX)\nadd_subdirectory(\"%s\" dngrid)\n' "$ROOT" \
    > "$parent/CMakeLists.txt"
  cmake -S "$parent" -B "$parent/build" -G Ninja >/dev/null
  if grep -qE 'dng_baker|dngdump|dngbake|gtest' "$parent/build/build.ninja"; then
    log "embedded with add_subdirectory, dngrid builds more than format and runtime"; exit 1
  fi
  if grep -q '^CMAKE_BUILD_TYPE:STRING=.' "$parent/build/CMakeCache.txt"; then
    log "embedded with add_subdirectory, dngrid set the parent's CMAKE_BUILD_TYPE"; exit 1
  fi
}

# Runtime-only build flags: every baker library made unfindable.
RUNTIME_ONLY_FLAGS=(-DCMAKE_BUILD_TYPE=Release -DDNG_BUILD_BAKER=OFF -DDNG_BUILD_BENCH=OFF -DDNG_BUILD_TESTS=ON
  -DCMAKE_DISABLE_FIND_PACKAGE_OpenMesh=ON -DCMAKE_DISABLE_FIND_PACKAGE_embree=ON
  -DCMAKE_DISABLE_FIND_PACKAGE_OpenVDB=ON -DCMAKE_DISABLE_FIND_PACKAGE_CLI11=ON -DCMAKE_DISABLE_FIND_PACKAGE_TBB=ON
  -DCMAKE_DISABLE_FIND_PACKAGE_TinyGLTF=ON -DCMAKE_DISABLE_FIND_PACKAGE_assimp=ON)

# 64-bit ARM: Debian's cross compiler, its C library, qemu-user to run the tests, GoogleTest's sources.
PACKAGES_AARCH64=(g++-aarch64-linux-gnu libc6-dev-arm64-cross qemu-user googletest)

# The runtime-only build cross-compiled for aarch64 (cmake/toolchains/aarch64-linux-gnu.cmake), its
# tests run under qemu-user through CMAKE_CROSSCOMPILING_EMULATOR. Debian has no aarch64 libgtest here
# (that would need the arm64 architecture in dpkg), so GoogleTest is built from /usr/src/googletest
# and installed into the build tree. dngdump and the samples need libpng for aarch64: left out.
cmd_aarch64() {
  install_packages "${PACKAGES_BUILD[@]}" "${PACKAGES_AARCH64[@]}"
  local build="$ROOT/build/aarch64" toolchain="$ROOT/cmake/toolchains/aarch64-linux-gnu.cmake"
  cmake -S /usr/src/googletest -B "$build/googletest" -G Ninja -DCMAKE_TOOLCHAIN_FILE="$toolchain" \
    -DCMAKE_BUILD_TYPE=Release -DBUILD_GMOCK=OFF -DCMAKE_INSTALL_PREFIX="$build/gtest" -DCMAKE_INSTALL_LIBDIR=lib \
    >/dev/null
  cmake --build "$build/googletest" --parallel "$JOBS"
  cmake --install "$build/googletest" >/dev/null
  configure_and_build "$build/dngrid" "${RUNTIME_ONLY_FLAGS[@]}" -DCMAKE_TOOLCHAIN_FILE="$toolchain" \
    -DDNG_BUILD_TOOLS=OFF -DDNG_BUILD_SAMPLES=OFF -DGTest_DIR="$build/gtest/lib/cmake/GTest"
  # A build that quietly fell back to the host compiler would pass everything: check the machine.
  if ! readelf -h "$build/dngrid/tests/particles_test" | grep -q 'Machine: *AArch64'; then
    log "the aarch64 build did not produce aarch64 programs"; exit 1
  fi
  run_tests "$build/dngrid"
}

# check_install <prefix> <file.dng> <ON|OFF: baker expected>: what a user of the installed tree does.
check_install() {
  local prefix="$1" dng="$2" baker="$3" work="$1/consumers"
  mkdir -p "$work"
  local pc_dir
  pc_dir=$(dirname "$(find "$prefix" -name dngrid.pc | head -n 1)")
  [ -f "$pc_dir/dngrid.pc" ] || { log "no dngrid.pc under $prefix"; exit 1; }
  local cflags libs libdir
  cflags=$(PKG_CONFIG_PATH="$pc_dir" pkg-config --cflags dngrid)
  libs=$(PKG_CONFIG_PATH="$pc_dir" pkg-config --libs dngrid)
  libdir=$(PKG_CONFIG_PATH="$pc_dir" pkg-config --variable=libdir dngrid)
  # shellcheck disable=SC2086 # the flags are words
  cc -std=c99 -Wall -Wextra -pedantic -Werror "$ROOT/tests/install/c_consumer.c" $cflags $libs \
    -Wl,-rpath,"$libdir" -o "$work/c_consumer"
  "$work/c_consumer" "$dng"
  cmake -S "$ROOT/tests/install/cpp_consumer" -B "$work/cpp" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" -DDNG_EXPECT_BAKER="$baker" >/dev/null
  cmake --build "$work/cpp" >/dev/null
  "$work/cpp/cpp_consumer" "$dng"
  sh "$ROOT/tests/check_exports.sh" "$libdir/libdngrid.so" "$ROOT/tests/abi/libdngrid.symbols"
  if [ "$baker" = ON ]; then
    [ -x "$prefix/bin/dngbake" ] && [ -x "$prefix/bin/dngdump" ] || { log "tools not installed"; exit 1; }
  elif [ -e "$prefix/bin/dngbake" ]; then
    log "the runtime-only install has dngbake"; exit 1
  fi
}

# Installs the full build and the runtime-only build into temporary prefixes and builds programs
# against each as an outside project would: C through pkg-config, C++ through find_package(dngrid).
PACKAGE_TMP=""
cmd_package() {
  deps
  PACKAGE_TMP=$(mktemp -d)
  trap 'rm -rf "$PACKAGE_TMP"' EXIT
  local tmp="$PACKAGE_TMP"
  configure_and_build "$ROOT/build/release" -DCMAKE_BUILD_TYPE=Release -DDNG_BUILD_TESTS=ON
  cmake --install "$ROOT/build/release" --prefix "$tmp/full" >/dev/null
  # A cube, baked by the installed dngbake, for the consumers to open.
  printf 'OFF\n8 6 0\n-1 -1 -1\n1 -1 -1\n-1 1 -1\n1 1 -1\n-1 -1 1\n1 -1 1\n-1 1 1\n1 1 1\n4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n' >"$tmp/cube.off"
  "$tmp/full/bin/dngbake" "$tmp/cube.off" -o "$tmp/cube.dng" --resolution 32 --quiet
  "$tmp/full/bin/dngdump" "$tmp/cube.dng" --check
  check_install "$tmp/full" "$tmp/cube.dng" ON
  configure_and_build "$ROOT/build/runtime-only" "${RUNTIME_ONLY_FLAGS[@]}"
  cmake --install "$ROOT/build/runtime-only" --prefix "$tmp/runtime" >/dev/null
  check_install "$tmp/runtime" "$tmp/cube.dng" OFF
  log "package: full and runtime-only installs build and run C and C++ consumers"
}

cmd_format_check() {
  install_packages clang-format git
  cd "$ROOT"
  git ls-files -- '*.h' '*.hpp' '*.cpp' '*.c' | xargs -r clang-format --dry-run --Werror
  log "clang-format: clean"
}

# The sample meshes come from Debian's libcgal-demo (docs/DESIGN.md §9) and are never committed.
# unpack_meshes FILE...: these meshes of Debian's libcgal-demo into data/data/meshes, where missing.
unpack_meshes() {
  install_packages libcgal-demo
  local meshes="$ROOT/data/data/meshes" wanted=() name
  for name in "$@"; do [ -f "$meshes/$name" ] || wanted+=("data/meshes/$name"); done
  [ ${#wanted[@]} -eq 0 ] && return 0
  mkdir -p "$ROOT/data"
  # Unpacked beside and moved into place: an interrupted unpack leaves no half file that a later run
  # would take for done.
  local unpack
  unpack=$(mktemp -d "$ROOT/data/.unpack.XXXXXX")
  tar -xzf /usr/share/doc/libcgal-dev/data.tar.gz -C "$unpack" "${wanted[@]}"
  mkdir -p "$meshes"
  mv "$unpack"/data/meshes/*.off "$meshes/"
  rm -rf "$unpack"
}

# The meshes the tests, the demo and the leak table use.
fetch_data() { unpack_meshes bunny00.off fandisk.off blade.off cheese.off mannequin-devil.off elephant-with-holes.off; }

build_fuzzers() {
  install_packages "${PACKAGES_BUILD[@]}" clang libclang-rt-14-dev libopenmesh-dev libtinygltf-dev libassimp-dev
  CC=clang CXX=clang++ configure_and_build "$ROOT/build/fuzz" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDNG_BUILD_FUZZ=ON \
    -DDNG_BUILD_BAKER=OFF -DDNG_BUILD_TESTS=OFF -DDNG_BUILD_SAMPLES=OFF -DDNG_BUILD_BENCH=OFF
}

# libFuzzer on View::open, then on dngdump's report path and on stepParticles (scalar against every SIMD
# set), seeded with the golden files and every file that once crashed dngdump; fails on any crash or
# sanitizer report. Then every mesh input that once crashed, hung or exhausted memory in OpenMesh's
# readers, which must now be refused cleanly.
# (Open-ended mesh fuzzing keeps finding new reader bugs: that is `fuzz-meshes`.)
cmd_fuzz() {
  build_fuzzers
  local build="$ROOT/build/fuzz" corpus="$ROOT/build/fuzz/corpus" seconds="${1:-60}"
  mkdir -p "$corpus"
  cp "$ROOT"/tests/golden/*.dng "$ROOT"/tests/fuzz/dump_regressions/* "$corpus/"
  "$build/tests/fuzz/fuzz_dump" "$ROOT"/tests/fuzz/dump_regressions/*
  "$build/tests/fuzz/fuzz_open" -max_total_time="$seconds" -max_len=65536 -print_final_stats=1 "$corpus"
  "$build/tests/fuzz/fuzz_dump" -max_total_time="$((seconds / 2))" -max_len=65536 -timeout=10 -print_final_stats=1 "$corpus"
  "$build/tests/fuzz/fuzz_step" -max_total_time="$((seconds / 2))" -max_len=65536 -timeout=10 -print_final_stats=1 "$corpus"
  "$build/tests/fuzz/fuzz_mesh" -timeout=10 -rss_limit_mb=2048 "$ROOT"/tests/fuzz/mesh_regressions/*
  "$build/tests/fuzz/fuzz_gltf" -timeout=10 -rss_limit_mb=2048 "$ROOT"/tests/fuzz/gltf_regressions/*
}

# libFuzzer on the glTF importer, seeded with a one-triangle .gltf (embedded buffer) and .glb.
cmd_fuzz_scenes() {
  build_fuzzers
  local build="$ROOT/build/fuzz" scenes="$ROOT/build/fuzz/gltf_corpus"
  mkdir -p "$scenes"
  cp "$ROOT"/tests/fuzz/gltf_regressions/* "$scenes/"
  "$build/tests/fuzz/fuzz_gltf" -max_total_time="${1:-300}" -max_len=4096 -timeout=10 -rss_limit_mb=2048 \
    -dict="$ROOT/tests/fuzz/gltf.dict" \
    -print_final_stats=1 "$scenes"
}

# libFuzzer on assimp in process (dngbake runs it in a child process, so its crashes are exit code 3;
# import_test replays tests/fuzz/assimp_regressions/ through dngbake). assimp leaks on some bad files:
# leak reports are off.
cmd_fuzz_assimp() {
  build_fuzzers
  local build="$ROOT/build/fuzz" corpus="$ROOT/build/fuzz/assimp_corpus"
  mkdir -p "$corpus"
  printf '\006*3DSMAX_ASCIIEXPORT 200\n*GEOMOBJECT {\n*NODE_NAME "a"\n*MESH {\n*MESH_NUMVERTEX 3\n*MESH_NUMFACES 1\n*MESH_VERTEX_LIST {\n*MESH_VERTEX 0 0 0 0\n*MESH_VERTEX 1 1 0 0\n*MESH_VERTEX 2 0 1 0\n}\n*MESH_FACE_LIST {\n*MESH_FACE 0: A: 0 B: 1 C: 2\n}\n}\n}\n' >"$corpus/ase"
  printf '\004xof 0303txt 0032\nMesh m {\n3;\n0;0;0;,\n1;0;0;,\n0;1;0;;\n1;\n3;0,1,2;;\n}\n' >"$corpus/x"
  "$build/tests/fuzz/fuzz_assimp" -max_total_time="${1:-300}" -max_len=4096 -timeout=10 -rss_limit_mb=2048 \
    -detect_leaks=0 -print_final_stats=1 "$corpus"
}

# libFuzzer on mesh loading, seeded with one triangle per format and the regressions.
cmd_fuzz_meshes() {
  build_fuzzers
  local build="$ROOT/build/fuzz" meshes="$ROOT/build/fuzz/mesh_corpus"
  mkdir -p "$meshes"
  cp "$ROOT"/tests/fuzz/mesh_regressions/* "$meshes/"
  # Mesh seeds: the first byte picks the format (0 OBJ, 1 OFF, 2 PLY, 3 STL), then a one-triangle file.
  printf '\000v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$meshes/obj"
  printf '\001OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >"$meshes/off"
  printf '\002ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' >"$meshes/ply"
  printf '\003solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n' >"$meshes/stl"
  # The binary variants: little-endian PLY, STL (80-byte header, a count, 50-byte facets), OFF BINARY
  # (little-endian counts and values, as OpenMesh reads them). One float: 1.0.
  local one_le='\000\000\200\077' z4='\000\000\000\000'
  printf "\002ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n$z4$z4$z4$one_le$z4$z4$z4$one_le$z4\003$z4\001\000\000\000\002\000\000\000" >"$meshes/ply_binary"
  { printf '\003binary'; printf '%74s' ''; printf "\001\000\000\000$z4$z4$one_le$z4$z4$z4$one_le$z4$z4$z4$one_le$z4\000\000"; } >"$meshes/stl_binary"
  printf "\001OFF BINARY\n\003\000\000\000\001\000\000\000$z4$z4$z4$z4$one_le$z4$z4$z4$one_le$z4\003\000\000\000$z4\001\000\000\000\002\000\000\000" >"$meshes/off_binary"
  "$build/tests/fuzz/fuzz_mesh" -max_total_time="${1:-300}" -max_len=4096 -timeout=10 -print_final_stats=1 "$meshes"
}

cmd_bench() {
  deps
  install_packages python3 gnuplot-nox # the report and its plot
  command -v npm >/dev/null || install_packages npm # the Table 1 meshes (bench/fetch_table1_meshes.sh)
  fetch_data
  configure_and_build "$ROOT/build/bench" -DCMAKE_BUILD_TYPE=Release -DDNG_BUILD_BENCH=ON -DDNG_BUILD_TESTS=OFF
  bash "$ROOT/bench/run.sh" "$ROOT/build/bench" "${1:-}"
}

# Every mesh and mode against every leak case, 20,000 particles x 120 steps each, judged on the
# original triangles (tests/leak/); 4-8 minutes on 2 cores.
cmd_leaks() {
  deps
  fetch_data
  local build="$ROOT/build/release"
  cmake -S "$ROOT" -B "$build" -G Ninja -DDNG_WERROR="$WERROR" -DCMAKE_BUILD_TYPE=Release -DDNG_BUILD_TESTS=ON >/dev/null
  cmake --build "$build" --parallel "$JOBS" --target leak_report
  "$build/tests/leak/leak_report" "$ROOT/data/data/meshes" "$ROOT/docs/LEAKS.md"
  log "wrote docs/LEAKS.md"
  # The same cases on more of libcgal-demo's meshes: animals, people, machine parts, a knot.
  local more=(ChineseDragon-10kv anchor_dense armadillo camel couplingdown cow elephant knot1 man mannequin-devil
              pinion rotor turbine) args=()
  unpack_meshes "${more[@]/%/.off}"
  for name in "${more[@]}"; do args+=(--mesh "$ROOT/data/data/meshes/$name.off"); done
  "$build/tests/leak/leak_report" "${args[@]}" "$ROOT/docs/LEAKS_MORE.md"
  log "wrote docs/LEAKS_MORE.md"
}

# The main job end to end: bake the Stanford bunny, check it, run particles around it, draw.
cmd_demo() {
  deps
  fetch_data
  local build="${DNG_DEMO_BUILD:-$ROOT/build/demo}" out="$ROOT/out"
  if [ -n "${DNG_DEMO_BUILD:-}" ]; then
    # CI reuses the test command's Release tree, which has the tools, samples and judge already built.
    cmake --build "$build" --parallel "$JOBS"
  else
    configure_and_build "$build" -DCMAKE_BUILD_TYPE=Release -DDNG_BUILD_TESTS=OFF -DDNG_BUILD_SAMPLES=ON
  fi
  mkdir -p "$out/demo" "$out/figures"
  local mesh="$ROOT/data/data/meshes/bunny00.off" dng="$out/demo/bunny.dng"
  local t0 t1
  t0=$(date +%s.%N)
  "$build/tools/dngbake" "$mesh" -o "$dng" --resolution 128 --quiet
  t1=$(date +%s.%N)
  "$build/tools/dngdump" "$dng" --check
  "$build/tools/dngdump" "$dng" --slice z=0 --png "$out/demo/bunny_field_slice.png"
  local stats
  stats=$("$build/samples/dng_demo" "$dng" "$out/demo" y "$out/demo/final_positions.txt") # bunny00.off is y-up
  echo "$stats" > "$out/demo/stats.json"
  # "Inside" is judged on the mesh's own triangles (ray parity), not by the field the particles used.
  local judged
  judged=$("$build/tests/reference/dng_count_inside" "$mesh" "$out/demo/final_positions.txt")
  log "running the paper's figures (Fig. 3, 6, 7, 8) and the thin sheet"
  "$build/samples/dng_fig3_falling" "$out/figures" > "$out/figures/fig3.json"
  "$build/samples/dng_fig6_sphere_flow" "$out/figures" > "$out/figures/fig6.json"
  "$build/samples/dng_fig7_shaft_flow" "$out/figures" > "$out/figures/fig7.json"
  "$build/samples/dng_fig8_explosion" "$out/figures" > "$out/figures/fig8.json"
  "$build/tools/dngbake" "$ROOT/data/data/meshes/blade.off" -o "$out/figures/blade.dng" --mode potential --quiet
  "$build/samples/dng_thin_sheet" "$out/figures/blade.dng" "$out/figures" > "$out/figures/thin_sheet.json"

  # Every particle the demo stepped must have been judged, or the count proves nothing.
  local inside rate bytes stepped judged_points
  json_number() { grep -o "\"$1\":[0-9.e+]*" <<<"$2" | cut -d: -f2 || { log "the demo's report has no \"$1\""; exit 1; }; }
  inside=$(json_number inside "$judged")
  judged_points=$(json_number points "$judged")
  stepped=$(json_number particles "$stats")
  rate=$(json_number particle_steps_per_second "$stats")
  [ "$judged_points" = "$stepped" ] || { log "judged $judged_points positions of $stepped particles"; exit 1; }
  bytes=$(stat -c %s "$dng")
  {
    echo "dngrid demo: the Stanford bunny (bunny00.off, 75,408 triangles)"
    printf '  bake time            %.2f s (resolution 128, normal-blur)\n' "$(echo "$t1 - $t0" | bc -l)"
    echo "  file size            $bytes bytes ($dng)"
    echo "  particles stepped    $rate particle-steps per second"
    echo "  particles inside     $inside by the mesh's triangles (must be 0)"
    echo "  pictures             $out/demo/*.png, $out/figures/*.png"
  } | tee "$out/summary.txt"
  [ "$inside" = "0" ] || { log "particles ended inside the mesh"; exit 1; }
}

case "${1:-}" in
  deps) deps ;;
  test) cmd_test ;;
  clang) cmd_clang ;;
  asan) cmd_asan ;;
  tsan) cmd_tsan ;;
  determinism) cmd_determinism ;;
  runtime-only) cmd_runtime_only ;;
  aarch64) cmd_aarch64 ;;
  package) cmd_package ;;
  format-check) cmd_format_check ;;
  bench) cmd_bench "${2:-}" ;;
  leaks) cmd_leaks ;;
  fuzz) cmd_fuzz "${2:-60}" ;;
  fuzz-meshes) cmd_fuzz_meshes "${2:-300}" ;;
  fuzz-scenes) cmd_fuzz_scenes "${2:-300}" ;;
  fuzz-assimp) cmd_fuzz_assimp "${2:-300}" ;;
  demo) cmd_demo ;;
  ccache-stats) cmd_ccache_stats ;;
  *) sed -n '2,25p' "$0" | sed 's/^# \{0,1\}//'; exit 1 ;;
esac
