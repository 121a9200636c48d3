// Fuzz target: a `.scn` text through the parser and the scene builder (`penalty info`'s path).
#include "fuzz_scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return penalty::fuzz::run_scene_input(data, size, 0);
}
