#include "view_server.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <fstream>
#include <memory>
#include <ostream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>

namespace penalty::apps {

namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_stop_signal(int /*signal*/) { g_stop.store(true); }

constexpr std::size_t kMaxHeaderBytes = 16 * 1024;
constexpr int kMaxConnections = 32;
constexpr int kIoTimeoutSeconds = 10;
constexpr std::size_t kMaxDrainBytes = 1024 * 1024;  ///< read and dropped after an early answer

std::string_view content_type(const std::filesystem::path& file) {
    const std::string ext = file.extension().string();
    if (ext == ".html") return "text/html; charset=utf-8";
    if (ext == ".js") return "text/javascript; charset=utf-8";
    if (ext == ".json") return "application/json";
    if (ext == ".csv") return "text/csv; charset=utf-8";
    if (ext == ".png") return "image/png";
    if (ext == ".f32" || ext == ".u32") return "application/octet-stream";
    return "text/plain; charset=utf-8";
}

bool valid_name(std::string_view name) {
    if (name.empty() || name.size() > 255 || name.front() == '.') return false;
    for (const char c : name) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
                        c == '.' || c == '-';
        if (!ok) return false;
    }
    return true;
}

/// Sends all of `data`; false when the peer went away or the write timed out.
bool send_all(int socket, const char* data, std::size_t size) {
    while (size > 0) {
        const ssize_t n = ::send(socket, data, size, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        data += n;
        size -= std::size_t(n);
    }
    return true;
}

void send_status(int socket, int status, std::string_view reason) {
    const std::string body = std::to_string(status) + " " + std::string(reason) + "\n";
    const std::string head = "HTTP/1.1 " + std::to_string(status) + " " + std::string(reason) +
                             "\r\nContent-Type: text/plain; charset=utf-8\r\nContent-Length: " +
                             std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n";
    if (send_all(socket, head.data(), head.size())) send_all(socket, body.data(), body.size());
}

/// Ends a connection whose request was not read to its end: stops sending, then reads and drops
/// what the client still sends (up to kMaxDrainBytes, for at most a second) before closing. Closing
/// with unread input makes the kernel reset the connection, and the reset can discard the answer
/// before the client reads it (the "lingering close" of HTTP servers).
void close_after_draining(int socket) {
    using Clock = std::chrono::steady_clock;
    ::shutdown(socket, SHUT_WR);
    const Clock::time_point deadline = Clock::now() + std::chrono::seconds(1);
    char buffer[4096];
    std::size_t drained = 0;
    while (drained < kMaxDrainBytes) {
        // each read waits at most until the deadline (a client trickling bytes cannot hold on)
        const auto left = std::chrono::duration_cast<std::chrono::microseconds>(deadline - Clock::now()).count();
        if (left <= 0) break;
        timeval timeout{static_cast<time_t>(left / 1000000), static_cast<suseconds_t>(left % 1000000)};
        ::setsockopt(socket, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
        const ssize_t n = ::recv(socket, buffer, sizeof buffer, 0);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;  // the client closed, or the deadline passed
        drained += std::size_t(n);
    }
    ::close(socket);
}

/// Reads one request, answers it, closes the socket. Never throws.
void handle_connection(int socket, const std::filesystem::path& directory) noexcept {
    try {
        timeval timeout{kIoTimeoutSeconds, 0};
        ::setsockopt(socket, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
        ::setsockopt(socket, SOL_SOCKET, SO_SNDTIMEO, &timeout, sizeof timeout);
        std::string request;
        char buffer[4096];
        while (request.find("\r\n\r\n") == std::string::npos && request.find("\n\n") == std::string::npos) {
            if (request.size() > kMaxHeaderBytes) {
                send_status(socket, 431, "Request Header Fields Too Large");
                close_after_draining(socket);
                return;
            }
            const ssize_t n = ::recv(socket, buffer, sizeof buffer, 0);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) break;  // closed, timed out or failed: answer what we have (or nothing)
            request.append(buffer, std::size_t(n));
        }
        if (request.empty()) {
            ::close(socket);
            return;
        }
        const std::size_t end = request.find_first_of("\r\n");
        const HttpResponse response = route_request(std::string_view(request).substr(0, end), directory);
        if (response.status != 200) {
            send_status(socket, response.status, response.reason);
        } else {
            std::ifstream in(response.file, std::ios::binary);
            std::error_code ec;
            const auto size = std::filesystem::file_size(response.file, ec);
            if (!in || ec) {
                send_status(socket, 404, "Not Found");
            } else {
                const std::string head = "HTTP/1.1 200 OK\r\nContent-Type: " + std::string(content_type(response.file)) +
                                         "\r\nContent-Length: " + std::to_string(size) +
                                         "\r\nCache-Control: no-store\r\nConnection: close\r\n\r\n";
                bool ok = send_all(socket, head.data(), head.size());
                std::uintmax_t left = response.head ? 0 : size;
                while (ok && left > 0 && in) {
                    in.read(buffer, std::streamsize(std::min<std::uintmax_t>(sizeof buffer, left)));
                    const auto got = std::size_t(in.gcount());
                    if (got == 0) break;
                    ok = send_all(socket, buffer, got);
                    left -= got;
                }
            }
        }
        ::shutdown(socket, SHUT_WR);
        ::close(socket);
    } catch (...) {  // NOLINT(bugprone-empty-catch): a bad request must never stop the server
        ::close(socket);
    }
}

}  // namespace

HttpResponse route_request(std::string_view line, const std::filesystem::path& directory) {
    const std::size_t sp1 = line.find(' ');
    const std::size_t sp2 = sp1 == std::string_view::npos ? sp1 : line.find(' ', sp1 + 1);
    if (sp1 == 0 || sp2 == std::string_view::npos || !line.substr(sp2 + 1).starts_with("HTTP/"))
        return {400, "Bad Request", {}, false};
    const std::string_view method = line.substr(0, sp1);
    std::string_view target = line.substr(sp1 + 1, sp2 - sp1 - 1);
    if (method != "GET" && method != "HEAD") return {405, "Method Not Allowed", {}, false};
    if (const std::size_t q = target.find_first_of("?#"); q != std::string_view::npos) target = target.substr(0, q);
    if (!target.starts_with('/')) return {400, "Bad Request", {}, false};
    std::string_view name = target.substr(1);
    if (name.empty()) name = "index.html";
    if (!valid_name(name)) return {404, "Not Found", {}, false};
    const std::filesystem::path file = directory / std::string(name);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) return {404, "Not Found", {}, false};
    return {200, "OK", file, method == "HEAD"};
}

void serve_directory(const std::filesystem::path& directory, int port, std::ostream& out) {
    const int listener = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (listener < 0) throw std::runtime_error(std::string("cannot create a socket: ") + std::strerror(errno));
    const int yes = 1;
    ::setsockopt(listener, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);  // 127.0.0.1 only: never reachable from another host
    if (::bind(listener, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0 || ::listen(listener, 64) != 0) {
        const std::string reason = std::strerror(errno);
        ::close(listener);
        throw std::runtime_error("cannot listen on 127.0.0.1:" + std::to_string(port) + ": " + reason);
    }
    socklen_t length = sizeof address;
    ::getsockname(listener, reinterpret_cast<sockaddr*>(&address), &length);
    out << "penalty view: serving " << directory.string() << " at http://127.0.0.1:" << ntohs(address.sin_port)
        << "/ (Ctrl-C to stop)" << std::endl;

    g_stop.store(false);
    std::signal(SIGINT, on_stop_signal);
    std::signal(SIGTERM, on_stop_signal);
    std::signal(SIGPIPE, SIG_IGN);
    auto active = std::make_shared<std::atomic<int>>(0);
    while (!g_stop.load()) {
        pollfd fd{listener, POLLIN, 0};
        if (::poll(&fd, 1, 200) <= 0) continue;  // timeout or EINTR: check the stop flag
        const int connection = ::accept4(listener, nullptr, nullptr, SOCK_CLOEXEC);
        if (connection < 0) continue;
        if (active->load() >= kMaxConnections) {
            send_status(connection, 503, "Service Unavailable");
            ::close(connection);
            continue;
        }
        active->fetch_add(1);
        try {
            std::thread([connection, directory, active] {
                handle_connection(connection, directory);
                active->fetch_sub(1);
            }).detach();
        } catch (const std::system_error&) {  // no thread available: answer on this one
            handle_connection(connection, directory);
            active->fetch_sub(1);
        }
    }
    ::close(listener);
    out << "penalty view: stopped" << std::endl;
}

}  // namespace penalty::apps
