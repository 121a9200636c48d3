#include "io/text.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace penalty::io::detail {

std::optional<std::string> unreadable_reason(const std::filesystem::path& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status link = fs::symlink_status(path, ec);
    if (ec || link.type() == fs::file_type::not_found) return "does not exist";
    const fs::file_status target = fs::status(path, ec);
    if (ec) {
        if (ec == std::errc::too_many_symbolic_link_levels) return "is a symbolic link loop";
        if (link.type() == fs::file_type::symlink) return "is a symbolic link to a missing file";
        return "cannot be examined (" + ec.message() + ")";
    }
    switch (target.type()) {
        case fs::file_type::regular:
            break;
        case fs::file_type::directory:
            return "is a directory, not a file";
        case fs::file_type::character:
            return "is a character device, not a regular file";
        case fs::file_type::block:
            return "is a block device, not a regular file";
        case fs::file_type::fifo:
            return "is a named pipe, not a regular file";
        case fs::file_type::socket:
            return "is a socket, not a regular file";
        case fs::file_type::not_found:
            return "is a symbolic link to a missing file";
        default:
            return "is not a regular file";
    }
    const std::uintmax_t bytes = fs::file_size(path, ec);
    if (ec) return "cannot be examined (" + ec.message() + ")";
    if (bytes > kMaxFileBytes) {
        return "is " + std::to_string(bytes >> 20) + " MiB (more than penalty's limit of " +
               std::to_string(kMaxFileBytes >> 20) + " MiB)";
    }
    return std::nullopt;
}

std::string read_file(const std::filesystem::path& path) {
    if (const auto why = unreadable_reason(path)) fail(path, 0, "cannot read: the path " + *why);
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, 0, "cannot open file");
    std::ostringstream out;
    out << in.rdbuf();
    if (in.bad()) fail(path, 0, "cannot read file");
    return std::move(out).str();
}

namespace {
bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }
}  // namespace

std::optional<double> parse_double(std::string_view token) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty() || token.front() == '+') return std::nullopt;
    double value = 0.0;
    const auto* first = token.data();
    const auto* last = token.data() + token.size();
    const auto [ptr, ec] = std::from_chars(first, last, value);
    if (ec != std::errc() || ptr != last || !std::isfinite(value)) return std::nullopt;
    return value;
}

std::optional<std::string> magnitude_problem(double value) {
    const double magnitude = std::abs(value);
    if (magnitude > kMaxMagnitude)
        return std::string("magnitude above 1e100 (penalty's limit for any number in a scene or mesh file)");
    if (magnitude > 0.0 && magnitude < kMinMagnitude)
        return std::string(
            "magnitude below 1e-100 (penalty's limit for a nonzero number in a scene or mesh "
            "file; write 0 for zero)");
    return std::nullopt;
}

std::optional<std::int64_t> parse_int(std::string_view token) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty() || token.front() == '+') return std::nullopt;
    std::int64_t value = 0;
    const auto* first = token.data();
    const auto* last = token.data() + token.size();
    const auto [ptr, ec] = std::from_chars(first, last, value);
    if (ec != std::errc() || ptr != last) return std::nullopt;
    return value;
}

std::vector<std::string_view> split_blanks(std::string_view text) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < text.size()) {
        while (i < text.size() && is_blank(text[i])) ++i;
        const std::size_t start = i;
        while (i < text.size() && !is_blank(text[i])) ++i;
        if (i > start) out.push_back(text.substr(start, i - start));
    }
    return out;
}

std::string_view trim(std::string_view text) {
    while (!text.empty() && is_blank(text.front())) text.remove_prefix(1);
    while (!text.empty() && is_blank(text.back())) text.remove_suffix(1);
    return text;
}

void fail(const std::filesystem::path& path, int line, const std::string& what) {
    if (line > 0) throw LoadError(path.string() + ":" + std::to_string(line) + ": " + what);
    throw LoadError(path.string() + ": " + what);
}

std::string_view skip_byte_order_mark(std::string_view text) {
    return text.starts_with("\xEF\xBB\xBF") ? text.substr(3) : text;
}

Tokenizer::Tokenizer(std::string_view text, std::filesystem::path path)
    : text_(skip_byte_order_mark(text)), path_(std::move(path)) {}

void Tokenizer::skip_blanks() {
    while (pos_ < text_.size() && is_blank(text_[pos_])) {
        if (text_[pos_] == '\n') ++line_;
        ++pos_;
    }
}

std::optional<Token> Tokenizer::next() {
    skip_blanks();
    if (pos_ >= text_.size()) return std::nullopt;  // token_line_ stays on the last token
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_blank(text_[pos_])) ++pos_;
    token_line_ = line_;
    return Token{text_.substr(start, pos_ - start), line_};
}

Token Tokenizer::expect(std::string_view what) {
    auto token = next();
    if (!token) fail(path_, token_line_, "unexpected end of file (expected " + std::string(what) + ")");
    return *token;
}

double Tokenizer::expect_double(std::string_view what) {
    const Token token = expect(what);
    const auto value = parse_double(token.text);
    if (!value) {
        fail(path_, token.line,
             "expected " + std::string(what) + " (a number), found '" + std::string(token.text) + "'");
    }
    if (const auto problem = magnitude_problem(*value))
        fail(path_, token.line, std::string(what) + " '" + std::string(token.text) + "': " + *problem);
    return *value;
}

std::int64_t Tokenizer::expect_int(std::string_view what) {
    const Token token = expect(what);
    const auto value = parse_int(token.text);
    if (!value) {
        fail(path_, token.line,
             "expected " + std::string(what) + " (an integer), found '" + std::string(token.text) + "'");
    }
    return *value;
}

std::string_view Tokenizer::rest_of_line() {
    const std::size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    const std::string_view rest = text_.substr(start, pos_ - start);
    if (pos_ < text_.size()) {
        ++pos_;
        ++line_;
    }
    return trim(rest);
}

void Tokenizer::check_count(std::int64_t count, int tokens_per_item, std::string_view what) const {
    // each token takes at least one character plus one separator (the last may end the file)
    const auto max_tokens = static_cast<std::int64_t>(remaining() / 2 + 1);
    if (count < 0) {
        fail(path_, token_line_, std::string(what) + " count " + std::to_string(count) + " is negative");
    }
    if (tokens_per_item > 0 && count > max_tokens / tokens_per_item) {
        fail(path_, token_line_,
             std::string(what) + " count " + std::to_string(count) + " exceeds what the file can hold");
    }
}

}  // namespace penalty::io::detail
