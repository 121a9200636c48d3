#pragma once
// `penalty view`: a small HTTP server for a viewer directory, bound to 127.0.0.1 only.

#include <filesystem>
#include <iosfwd>
#include <string_view>

namespace penalty::apps {

/// The response to one HTTP request for a file of `directory` (exposed for tests of the parser):
/// GET or HEAD of "/" (index.html) or "/<name>" with name in [A-Za-z0-9_.-], not starting with
/// '.', a regular file directly in `directory`. Anything else: 400 (malformed request line),
/// 404 (other names, sub-paths, "..", percent escapes), 405 (other methods).
struct HttpResponse {
    int status = 200;
    std::string_view reason = "OK";
    std::filesystem::path file;  ///< the file to send (status 200)
    bool head = false;           ///< HEAD: headers only
};
[[nodiscard]] HttpResponse route_request(std::string_view request_line, const std::filesystem::path& directory);

/// Serves `directory` on http://127.0.0.1:port/ (port 0: a free port chosen by the system) until
/// SIGINT or SIGTERM; prints the address on `out` once listening. Each connection is answered on
/// its own thread (at most 32 at once) with one response, then closed; reads and writes time out
/// after 10 s, so a silent client cannot block the server. Throws std::runtime_error when the
/// socket cannot be bound (port in use, ...).
void serve_directory(const std::filesystem::path& directory, int port, std::ostream& out);

}  // namespace penalty::apps
