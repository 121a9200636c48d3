#pragma once
/// @file
/// Number formatting shared by the output writers, and the error they raise when a value to be
/// written is not finite (a diverging simulation).
///
/// Numbers are written in the shortest form that reads back to the same double
/// (std::to_chars without precision): -5 -> "-5", 0 -> "0", 0.1 -> "0.1", 1e-300 -> "1e-300".

#include <stdexcept>
#include <string>
#include <string_view>

namespace penalty::output {

/// Thrown by every writer, before anything is written for the step, when a value to write is NaN
/// or infinite. The message names the file or state, the item (DOF, contact, column) and the time.
/// Derived from std::runtime_error, so catching runtime_error catches I/O and divergence alike.
class NonFiniteValueError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Appends the shortest round-trip decimal form of `value` to `out` (std::to_chars).
/// Non-finite values are written as "inf", "-inf" or "nan" (to_chars' spelling); writers check
/// finiteness before formatting, so this only happens in messages.
void append_number(std::string& out, double value);

/// The shortest round-trip decimal form of `value`.
[[nodiscard]] std::string format_number(double value);

/// Replaces every character outside [A-Za-z0-9_.-] by '_' (an empty name becomes "state"), so a
/// component name can be used in a file name.
[[nodiscard]] std::string sanitize_file_name(std::string_view name);

}  // namespace penalty::output
