// Fuzz target: the request parser and router of `penalty view` (apps/penalty/http_request.hpp) on
// arbitrary bytes. Besides crashes and sanitizer reports, a broken invariant is a finding (trap):
//  - a complete head lies within the input and kMaxHeadBytes; parsing the head alone, or the input
//    with more bytes after it, gives the same answer, and every strict prefix of it is incomplete;
//  - a refusal is 400, 431 or 505, and more input never turns it into something else;
//  - incomplete input is shorter than kMaxHeadBytes;
//  - a routed name is a servable name: one path component, never "." or "..", never hidden;
//  - a Host the server accepts names the loopback interface.
#include "http_request.hpp"

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace {

using penalty::apps::http::ParsedHead;
namespace http = penalty::apps::http;

void require(bool condition) {
    if (!condition) __builtin_trap();
}

bool same(const ParsedHead& a, const ParsedHead& b) {
    return a.outcome == b.outcome && a.status.code == b.status.code && a.method == b.method && a.target == b.target &&
           a.host == b.host && a.head_bytes == b.head_bytes;
}

bool starts_with_ignoring_case(std::string_view text, std::string_view prefix) {
    if (text.size() < prefix.size()) return false;
    for (std::size_t i = 0; i < prefix.size(); ++i)
        if ((text[i] | 0x20) != (prefix[i] | 0x20)) return false;
    return true;
}

void check_route(std::string_view method, std::string_view target) {
    const http::Route route = http::route_request(method, target);
    if (route.status.code != 200) {
        require(route.status.code == 400 || route.status.code == 404 || route.status.code == 405);
        return;
    }
    require(method == "GET" || method == "HEAD");
    require(http::is_servable_name(route.name));
    require(route.name.find('/') == std::string::npos && route.name.front() != '.' &&
            route.name.find('\0') == std::string::npos);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view input(reinterpret_cast<const char*>(data), size);
    const ParsedHead whole = http::parse_request_head(input);
    switch (whole.outcome) {
        case ParsedHead::Outcome::complete: {
            require(whole.head_bytes > 0 && whole.head_bytes <= size && whole.head_bytes <= http::kMaxHeadBytes);
            const std::string_view head = input.substr(0, whole.head_bytes);
            require(same(http::parse_request_head(head), whole));
            require(whole.method.data() >= head.data() &&
                    whole.target.data() + whole.target.size() <= head.data() + head.size());
            for (const std::size_t cut : {std::size_t(0), whole.head_bytes / 2, whole.head_bytes - 1})
                require(http::parse_request_head(head.substr(0, cut)).outcome == ParsedHead::Outcome::incomplete);
            check_route(whole.method, whole.target);
            if (http::is_loopback_host(whole.host))
                require(whole.host.empty() || starts_with_ignoring_case(whole.host, "localhost") ||
                        whole.host.starts_with("127.0.0.1") || whole.host.starts_with("[::1]"));
            break;
        }
        case ParsedHead::Outcome::refused: {
            const int code = whole.status.code;
            require(code == 400 || code == 431 || code == 505);
            if (code == 431) require(size >= http::kMaxHeadBytes);
            const ParsedHead longer = http::parse_request_head(std::string(input) + "\r\n\r\nGET / HTTP/1.1\r\n\r\n");
            require(longer.outcome == ParsedHead::Outcome::refused && longer.status.code == code);
            break;
        }
        case ParsedHead::Outcome::incomplete:
            require(size < http::kMaxHeadBytes);
            break;
    }
    // The router and the Host check on their own, on the raw input split at its first space.
    const std::size_t space = input.find(' ');
    if (space != std::string_view::npos) check_route(input.substr(0, space), input.substr(space + 1));
    if (http::is_loopback_host(input))
        require(input.empty() || starts_with_ignoring_case(input, "localhost") || input.starts_with("127.0.0.1") ||
                input.starts_with("[::1]"));
    return 0;
}
