# penalty::warnings: warnings and determinism flags, linked PRIVATE (never exported to users).
add_library(penalty_warnings INTERFACE)
add_library(penalty::warnings ALIAS penalty_warnings)
target_compile_options(penalty_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align -Woverloaded-virtual
  -Wnull-dereference -Wdouble-promotion -Wimplicit-fallthrough
  # bit-identical results across builds: no fused multiply-add contraction
  -ffp-contract=off)

# Fuzzing (clang only): every library object is instrumented for libFuzzer's coverage and
# checked by ASan + UBSan; the fuzz targets (fuzz/) link libFuzzer's main.
if(PENALTY_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "PENALTY_FUZZ needs clang++ (libFuzzer): configure with the 'fuzz' preset")
  endif()
  set(_penalty_fuzz -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_compile_options(${_penalty_fuzz})
  add_link_options(-fsanitize=address,undefined)
endif()
if(PENALTY_SANITIZE)
  set(_penalty_san -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_compile_options(${_penalty_san})
  add_link_options(${_penalty_san})
endif()
