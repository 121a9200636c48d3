#pragma once
// `penalty view`: a small HTTP server for a viewer directory, bound to 127.0.0.1 only
// (docs/viewer.md, "The server"). Requests are parsed and routed by http_request.hpp.

#include <filesystem>
#include <iosfwd>

namespace penalty::apps {

/// Serves `directory` on http://127.0.0.1:port/ (port 0: a free port chosen by the system) until
/// SIGINT or SIGTERM; prints the address on `out` once listening. One thread, non-blocking
/// sockets and poll(2): a slow or silent client holds a connection slot, never the server.
/// Each connection gets one response and is closed. Limits: the request head must arrive whole
/// within 10 s of the connection (then 408), a response must make progress every 10 s, and at
/// most 256 connections are open at once (a new one closes the oldest that has not sent its whole
/// request). Files are opened relative to the directory (opened once, at the start) with
/// O_NOFOLLOW: only regular files directly in it, never a symbolic link, a FIFO or a device.
/// Throws std::runtime_error when the directory cannot be opened or the socket cannot be bound.
void serve_directory(const std::filesystem::path& directory, int port, std::ostream& out);

}  // namespace penalty::apps
