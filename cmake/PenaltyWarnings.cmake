# penalty::warnings: warnings and determinism flags, linked PRIVATE (never exported to users).
add_library(penalty_warnings INTERFACE)
add_library(penalty::warnings ALIAS penalty_warnings)
target_compile_options(penalty_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wcast-align -Woverloaded-virtual
  -Wnull-dereference -Wdouble-promotion -Wimplicit-fallthrough
  # bit-identical results across builds: no fused multiply-add contraction
  -ffp-contract=off)

if(PENALTY_SANITIZE)
  set(_penalty_san -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_compile_options(${_penalty_san})
  add_link_options(${_penalty_san})
endif()
