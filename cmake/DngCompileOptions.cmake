# Warnings for every dngrid target, and the sanitizer build types CI uses: cmake -DCMAKE_BUILD_TYPE=ASan
# (AddressSanitizer + UndefinedBehaviorSanitizer) or -DCMAKE_BUILD_TYPE=TSan (ThreadSanitizer).
#
# The sanitizer flags are attached with generator expressions rather than CMAKE_CXX_FLAGS_ASAN: CMake
# creates that cache entry (empty) as soon as the build type is named, so a cached default never lands.
# Line tables only (-g1): the reports' stack traces need no more, and full debug info for the SIMD
# kernels' inlined code more than doubled their compile times (batch_avx512.cpp: 173 s against 74 s).
set(DNG_SANITIZE_FLAGS -O1 -g1 -fno-omit-frame-pointer -fsanitize=address,undefined -fno-sanitize-recover=all)
add_compile_options("$<$<CONFIG:ASan>:${DNG_SANITIZE_FLAGS}>")
add_link_options("$<$<CONFIG:ASan>:-fsanitize=address,undefined>")
set(DNG_UBSAN_IGNORELIST ${CMAKE_CURRENT_LIST_DIR}/ubsan-ignorelist.txt) # clang only: what it leaves out, and why
add_compile_options("$<$<AND:$<CONFIG:ASan>,$<CXX_COMPILER_ID:Clang>>:-fsanitize-ignorelist=${DNG_UBSAN_IGNORELIST}>")
add_compile_options("$<$<CONFIG:TSan>:-O1;-g1;-fno-omit-frame-pointer;-fsanitize=thread>")
add_link_options("$<$<CONFIG:TSan>:-fsanitize=thread>")
# GCC's points-to analysis grows faster than linearly with a function's size, and the SIMD kernels'
# force-inlined step is one very large function: without it batch_sse41.cpp compiles under ASan in 45 s
# instead of 72 (batch_avx512.cpp 58 s instead of 75; the whole GCC ASan build and tests 545 s -> 513 s). It
# only feeds optimisation; the sanitizer's checks are the same. Under TSan the unit compiles in 14 s either
# way. CI builds ASan with clang (setup.sh asan), which compiles the instrumented units in less time still.
add_compile_options("$<$<AND:$<CONFIG:ASan>,$<CXX_COMPILER_ID:GNU>>:-fno-tree-pta>")

# dng_target_warnings(<target>): -Wall -Wextra and friends; -Werror when DNG_WERROR is on.
function(dng_target_warnings target)
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion
                                             $<$<BOOL:${DNG_WERROR}>:-Werror>)
  elseif(MSVC)
    target_compile_options(${target} PRIVATE /W4 $<$<BOOL:${DNG_WERROR}>:/WX>)
  endif()
endfunction()
