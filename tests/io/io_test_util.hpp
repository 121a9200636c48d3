#pragma once
// Helpers for the io tests: committed data folder and temporary files with given contents.

#include "penalty_test/paths.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

namespace penalty::io::test {

/// tests/io/data in the source tree.
inline std::filesystem::path data_dir() { return penalty::test::source_dir() / "tests" / "io" / "data"; }

/// A fresh file under the test temporary directory with exactly `contents`.
inline std::filesystem::path write_temp(const std::string& name, const std::string& contents) {
    const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "penalty_io_tests";
    std::filesystem::create_directories(dir);
    const std::filesystem::path path = dir / name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << contents;
    return path;
}

/// The message of the exception of type E thrown by f; fails the test when none is thrown.
template <class E>
std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const E& e) {
        return e.what();
    }
    ADD_FAILURE() << "no exception thrown";
    return {};
}

}  // namespace penalty::io::test
