#pragma once
// The request side of `penalty view`'s HTTP server (docs/viewer.md, "The server"): parsing a
// request head (RFC 9112 §2–5, the subset a static file server needs) and routing its target to a
// file name of the served directory. Pure functions of their input, no socket and no file system:
// the libFuzzer target fuzz/fuzz_http_request.cpp runs them on arbitrary bytes.

#include <cstddef>
#include <string>
#include <string_view>

namespace penalty::apps::http {

/// The most bytes a request head may have: request line, header lines and the empty line that ends
/// them, line ends included. One more is answered 431.
inline constexpr std::size_t kMaxHeadBytes = 16 * 1024;

/// A status the server answers with.
struct Status {
    int code = 200;
    std::string_view reason = "OK";
};

/// What the bytes received so far make of a request head.
struct ParsedHead {
    enum class Outcome {
        incomplete,  ///< no empty line yet, at most kMaxHeadBytes received: read more
        complete,    ///< a well-formed head of `head_bytes` bytes: route method and target
        refused,     ///< answer `status` (400, 431, 505) and close
    };
    Outcome outcome = Outcome::incomplete;
    Status status;            ///< refused: the answer
    std::string_view method;  ///< complete: views into the parsed bytes
    std::string_view target;
    std::string_view host;       ///< the Host field's value, empty when absent
    std::size_t head_bytes = 0;  ///< complete: the head's size; bytes after it are a body (ignored)
};

/// Parses the start of `received`. Lines end with LF, optionally preceded by CR; the head ends at
/// the first empty line. The result depends only on the head: bytes after it never change it, and
/// every strict prefix of a complete head is `incomplete` (or 431 once it passed kMaxHeadBytes).
/// Refused (400): a request line that is not `METHOD SP TARGET SP HTTP/1.x` (method a token,
/// target visible ASCII), a header line without a token name and a colon, whitespace before a
/// name (obsolete line folding), control characters, two Host fields. 505: HTTP/2 or later.
/// 431: more than kMaxHeadBytes before the end of the head.
[[nodiscard]] ParsedHead parse_request_head(std::string_view received);

/// True when a Host field names this machine's loopback interface (`127.0.0.1`, `localhost`,
/// `[::1]`, with any port) or is absent. Any other host means the page was reached through a
/// name an outside web site controls (DNS rebinding): the server refuses it (421).
[[nodiscard]] bool is_loopback_host(std::string_view host);

/// Where a request goes: a file of the served directory or an error status.
struct Route {
    Status status;           ///< 200: serve `name`
    std::string name;        ///< a name valid for is_servable_name
    bool head_only = false;  ///< HEAD: the headers without the body
};

/// GET or HEAD of "/" (index.html) or "/<name>" (query and fragment ignored) with
/// is_servable_name(name): 200 and the name. Other methods 405; a target not starting with '/'
/// 400; anything else (sub-paths, "..", percent escapes, hidden names) 404.
[[nodiscard]] Route route_request(std::string_view method, std::string_view target);

/// Names made of [A-Za-z0-9_.-], 1 to 255 characters, not starting with '.': never a path (no
/// '/'), never "." or "..", never one of the writer's temporary files (which start with '.').
[[nodiscard]] bool is_servable_name(std::string_view name);

}  // namespace penalty::apps::http
