// penalty_test/paths.hpp: the folders, from the definitions tests/CMakeLists.txt gives this file alone.
#include "penalty_test/paths.hpp"

namespace penalty::test {

std::filesystem::path source_dir() { return PENALTY_SOURCE_DIR; }
std::filesystem::path shared_dir() { return PENALTY_SHARED_DIR; }

}  // namespace penalty::test
