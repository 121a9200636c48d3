#include "penalty/output/format.hpp"

#include <array>
#include <charconv>

namespace penalty::output {

void append_number(std::string& out, double value) {
    std::array<char, 32> buffer{};  // the shortest round-trip form of a double takes ≤ 24 chars
    const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
    out.append(buffer.data(), result.ptr);
}

std::string format_number(double value) {
    std::string out;
    append_number(out, value);
    return out;
}

std::string sanitize_file_name(std::string_view name) {
    if (name.empty()) return "state";
    std::string out(name);
    for (char& c : out) {
        const bool keep = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
                          c == '-' || c == '.';
        if (!keep) c = '_';
    }
    return out;
}

}  // namespace penalty::output
