# penalty::warnings: warnings and determinism flags, linked PRIVATE (never exported to users).
add_library(penalty_warnings INTERFACE)
add_library(penalty::warnings ALIAS penalty_warnings)
target_compile_options(penalty_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align -Woverloaded-virtual
  -Wnull-dereference -Wdouble-promotion -Wimplicit-fallthrough
  # bit-identical results across builds: no fused multiply-add contraction
  -ffp-contract=off)

# Sanitizers: ASan + UBSan on every object (PENALTY_SANITIZE, or PENALTY_FUZZ which implies it).
# Fuzzing (clang only): the library's layers are also instrumented for libFuzzer's coverage
# (cmake/PenaltyLayer.cmake) and the fuzz targets (fuzz/) link libFuzzer's main. The tests and
# the command line of the same build link the instrumented layers without libFuzzer (the
# sanitizer runtime provides the coverage callbacks): one sanitizer build, preset `asan`, serves
# the test suite and the fuzzers.
if(PENALTY_FUZZ AND NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
  message(FATAL_ERROR "PENALTY_FUZZ needs clang++ (libFuzzer): configure with the 'asan' preset")
endif()
if(PENALTY_WITH_SANITIZERS)
  set(_penalty_san -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_compile_options(${_penalty_san})
  add_link_options(${_penalty_san})
endif()
