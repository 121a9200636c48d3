#pragma once
/// @file
/// Internal text helpers of the io layer: whole-file reading, number parsing, a whitespace
/// tokenizer that tracks line numbers, and error formatting.

#include "penalty/io/error.hpp"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace penalty::io::detail {

/// Largest file penalty reads (bytes): 2 GiB. A bigger scene or mesh is refused before reading.
inline constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t(2) << 30;

/// Why `path` cannot be read as a data file, or nullopt when it is a readable regular file of at
/// most kMaxFileBytes: "does not exist", "is a directory", "is a symbolic link loop",
/// "is a character device (not a regular file)", "is 3.1 GiB (more than 2 GiB)", ...
/// Never reads the file, so a device (/dev/zero) or a FIFO cannot hang it.
std::optional<std::string> unreadable_reason(const std::filesystem::path& path);

/// Reads a whole regular file; throws LoadError `path: <unreadable_reason>` or
/// `path: cannot open file` when it cannot be read.
std::string read_file(const std::filesystem::path& path);

/// `text` without a leading UTF-8 byte-order mark (EF BB BF), which editors on Windows write at
/// the start of text files; every parser of a text file starts with it, so the first line's
/// first token is read as written.
[[nodiscard]] std::string_view skip_byte_order_mark(std::string_view text);

/// Parses a finite double from the whole token (leading '+' allowed); nullopt otherwise.
std::optional<double> parse_double(std::string_view token);

/// Largest magnitude of any number in a scene or mesh file: 1e100. No physical quantity in any
/// unit system comes near it, and products of two or three such numbers (m·g, ks·dt², …) stay
/// finite, so a value that would overflow the solve is refused where it is written.
inline constexpr double kMaxMagnitude = 1e100;
/// Smallest magnitude of a nonzero number in a scene or mesh file: 1e-100, the other end. A
/// quotient or product of two or three such numbers (ks = k1·k2/d, m·g, ks·dt²) stays a normal
/// double, neither overflowing (1/1e-308 = inf) nor vanishing below the solver's thresholds
/// (a mass of 1e-300 kg, a dt of 1e-300 s). SOFA's files use nothing below 1e-20.
inline constexpr double kMinMagnitude = 1e-100;

/// "magnitude above 1e100 (...)" when |value| > kMaxMagnitude, "magnitude below 1e-100 (...)"
/// when 0 < |value| < kMinMagnitude, nullopt otherwise.
std::optional<std::string> magnitude_problem(double value);
/// Parses a 64-bit signed integer from the whole token (leading '+' allowed); nullopt otherwise.
std::optional<std::int64_t> parse_int(std::string_view token);

/// Splits on blanks (space, tab, CR, LF, VT, FF).
std::vector<std::string_view> split_blanks(std::string_view text);

/// Removes leading and trailing blanks.
std::string_view trim(std::string_view text);
/// The text in single quotes, as error messages show a token: 'text'.
inline std::string quoted(std::string_view text) {
    std::string out;  // built by appends: GCC 12 warns (-Wrestrict, a false positive) on "'" + string
    out.reserve(text.size() + 2);
    out += '\'';
    out += text;
    out += '\'';
    return out;
}

/// `path:line: what` (or `path: what` when line <= 0), as a LoadError.
[[noreturn]] void fail(const std::filesystem::path& path, int line, const std::string& what);

/// A token and the 1-based line it starts on.
struct Token {
    std::string_view text;
    int line = 0;
};

/// Whitespace tokenizer over a whole file, tracking line numbers. Tokens are views into the
/// text given at construction, which must outlive the tokenizer.
class Tokenizer {
public:
    Tokenizer(std::string_view text, std::filesystem::path path);

    /// Next token, or nullopt at the end of the text.
    std::optional<Token> next();
    /// Next token; at the end of the text throws `path:line: unexpected end of file (expected <what>)`.
    Token expect(std::string_view what);
    /// Next token as a finite double / integer; throws naming `what` on a bad or missing token.
    double expect_double(std::string_view what);
    std::int64_t expect_int(std::string_view what);
    /// The rest of the current line (without the newline), trimmed; moves to the next line.
    std::string_view rest_of_line();
    /// Bytes not read yet (an upper bound for the number of tokens left is remaining()/2 + 1).
    [[nodiscard]] std::size_t remaining() const { return text_.size() - pos_; }
    /// Line of the last token returned (or the current line before any token).
    [[nodiscard]] int line() const { return token_line_; }
    [[nodiscard]] const std::filesystem::path& path() const { return path_; }

    /// Throws LoadError when `count` items of at least `tokens_per_item` tokens each cannot fit in
    /// the rest of the file: `path:line: <what> count N exceeds what the file can hold`.
    void check_count(std::int64_t count, int tokens_per_item, std::string_view what) const;

private:
    void skip_blanks();
    std::string_view text_;
    std::filesystem::path path_;
    std::size_t pos_ = 0;
    int line_ = 1;        // line of the read position
    int token_line_ = 1;  // line of the last token
};

}  // namespace penalty::io::detail
