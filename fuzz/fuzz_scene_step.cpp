// Fuzz target: a `.scn` text built, then stepped 3 times (`penalty run --steps 3`'s path).
#include "fuzz_scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return penalty::fuzz::run_scene_input(data, size, 3);
}
