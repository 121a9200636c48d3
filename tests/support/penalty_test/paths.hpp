#pragma once
/// @file
/// The folders the tests read data from, compiled into one small library (tests/support/paths.cpp)
/// so that no test's text holds an absolute path: ccache finds the tests' unity batches in any
/// checkout of the project.

#include <filesystem>

namespace penalty::test {

/// The project's source folder (tests' data, scenes, fuzz dictionaries).
[[nodiscard]] std::filesystem::path source_dir();
/// The folder of SOFA's shared files, `<source>/../shared`; the tests that need it skip, visibly,
/// where it is absent.
[[nodiscard]] std::filesystem::path shared_dir();

}  // namespace penalty::test
