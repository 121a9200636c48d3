#include "http_request.hpp"

#include <algorithm>
#include <cctype>

namespace penalty::apps::http {

namespace {

constexpr Status kBadRequest{400, "Bad Request"};

bool is_token_char(char c) {  // RFC 9110 §5.6.2 tchar
    const bool alnum = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
    return alnum || std::string_view("!#$%&'*+-.^_`|~").find(c) != std::string_view::npos;
}

bool is_token(std::string_view text) { return !text.empty() && std::all_of(text.begin(), text.end(), is_token_char); }

bool is_visible(char c) { return c > 0x20 && c < 0x7f; }

/// A field value's bytes (RFC 9110 §5.5): visible ASCII, space, tab and obs-text (0x80–0xff).
bool is_field_value_char(char c) {
    const auto u = static_cast<unsigned char>(c);
    return u == '\t' || (u >= 0x20 && u != 0x7f);
}

bool equals_ignoring_case(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
           });
}

std::string_view trim_spaces(std::string_view text) {
    while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
    return text;
}

/// `METHOD SP TARGET SP HTTP/d.d` into `head`; the status to refuse with otherwise.
bool parse_request_line(std::string_view line, ParsedHead& head) {
    const std::size_t sp1 = line.find(' ');
    const std::size_t sp2 = sp1 == std::string_view::npos ? sp1 : line.find(' ', sp1 + 1);
    if (sp2 == std::string_view::npos) return false;
    const std::string_view method = line.substr(0, sp1);
    const std::string_view target = line.substr(sp1 + 1, sp2 - sp1 - 1);
    const std::string_view version = line.substr(sp2 + 1);
    if (!is_token(method) || target.empty() || !std::all_of(target.begin(), target.end(), is_visible)) return false;
    const auto digit = [](char c) { return c >= '0' && c <= '9'; };
    if (version.size() != 8 || !version.starts_with("HTTP/") || !digit(version[5]) || version[6] != '.' ||
        !digit(version[7]))
        return false;
    if (version[5] != '1') {
        head.status = {505, "HTTP Version Not Supported"};
        return false;
    }
    head.method = method;
    head.target = target;
    return true;
}

ParsedHead refuse(Status status) {
    ParsedHead head;
    head.outcome = ParsedHead::Outcome::refused;
    head.status = status;
    return head;
}

}  // namespace

ParsedHead parse_request_head(std::string_view received) {
    // The head ends with the first empty line; find it without looking past kMaxHeadBytes.
    std::size_t head_bytes = 0;
    for (std::size_t pos = 0;;) {
        const std::size_t lf = received.find('\n', pos);
        if (lf >= kMaxHeadBytes) {  // npos (no line end yet) included: npos > kMaxHeadBytes
            // The end of the head, if it ever comes, lies beyond byte kMaxHeadBytes.
            if (lf != std::string_view::npos || received.size() >= kMaxHeadBytes)
                return refuse({431, "Request Header Fields Too Large"});
            return {};
        }
        const std::size_t length = lf - pos - (lf > pos && received[lf - 1] == '\r' ? 1 : 0);
        pos = lf + 1;
        if (length == 0) {
            head_bytes = pos;
            break;
        }
    }

    ParsedHead head;
    head.status = kBadRequest;
    bool have_host = false;
    bool first = true;
    for (std::size_t pos = 0; pos < head_bytes;) {
        const std::size_t lf = received.find('\n', pos);
        std::string_view line = received.substr(pos, lf - pos);
        pos = lf + 1;
        if (line.ends_with('\r')) line.remove_suffix(1);
        if (line.empty()) break;  // the end of the head
        if (!std::all_of(line.begin(), line.end(), is_field_value_char)) return refuse(kBadRequest);
        if (first) {
            first = false;
            if (!parse_request_line(line, head)) return refuse(head.status);
            continue;
        }
        const std::size_t colon = line.find(':');
        if (colon == std::string_view::npos || !is_token(line.substr(0, colon))) return refuse(kBadRequest);
        if (equals_ignoring_case(line.substr(0, colon), "host")) {
            if (have_host) return refuse(kBadRequest);  // RFC 9112 §3.2: exactly one
            have_host = true;
            head.host = trim_spaces(line.substr(colon + 1));
        }
    }
    if (first) return refuse(kBadRequest);  // an empty line where the request line should be
    head.outcome = ParsedHead::Outcome::complete;
    head.status = {200, "OK"};
    head.head_bytes = head_bytes;
    return head;
}

bool is_loopback_host(std::string_view host) {
    if (host.empty()) return true;
    const auto is_port = [](std::string_view port) {
        const auto digit = [](char c) { return c >= '0' && c <= '9'; };
        return !port.empty() && port.size() <= 5 && std::all_of(port.begin(), port.end(), digit);
    };
    std::string_view name = host;
    if (host.front() == '[') {  // an IPv6 literal, then an optional ":port"
        const std::size_t close = host.find(']');
        if (close == std::string_view::npos) return false;
        name = host.substr(0, close + 1);
        const std::string_view rest = host.substr(close + 1);
        if (!rest.empty() && !(rest.front() == ':' && is_port(rest.substr(1)))) return false;
    } else if (const std::size_t colon = host.find(':'); colon != std::string_view::npos) {
        name = host.substr(0, colon);
        if (!is_port(host.substr(colon + 1))) return false;
    }
    return equals_ignoring_case(name, "localhost") || name == "127.0.0.1" || name == "[::1]";
}

bool is_servable_name(std::string_view name) {
    if (name.empty() || name.size() > 255 || name.front() == '.') return false;
    return std::all_of(name.begin(), name.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '.' ||
               c == '-';
    });
}

Route route_request(std::string_view method, std::string_view target) {
    Route route;
    if (method != "GET" && method != "HEAD") {
        route.status = {405, "Method Not Allowed"};
        return route;
    }
    if (const std::size_t q = target.find_first_of("?#"); q != std::string_view::npos) target = target.substr(0, q);
    if (!target.starts_with('/')) {
        route.status = kBadRequest;
        return route;
    }
    std::string_view name = target.substr(1);
    if (name.empty()) name = "index.html";
    if (!is_servable_name(name)) {
        route.status = {404, "Not Found"};
        return route;
    }
    route.name = std::string(name);
    route.head_only = method == "HEAD";
    return route;
}

}  // namespace penalty::apps::http
