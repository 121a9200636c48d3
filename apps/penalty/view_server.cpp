#include "view_server.hpp"

#include "http_request.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/sendfile.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <memory>
#include <ostream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace penalty::apps {

namespace {

using Clock = std::chrono::steady_clock;

std::atomic<bool> g_stop{false};
extern "C" void on_stop_signal(int /*signal*/) { g_stop.store(true); }

constexpr auto kRequestDeadline = std::chrono::seconds(10);  ///< accept → whole request head received
constexpr auto kSendStallLimit = std::chrono::seconds(10);   ///< longest wait for the client to take more bytes
constexpr auto kDrainLimit = std::chrono::seconds(1);        ///< lingering close: reading what the client still sends
constexpr std::size_t kMaxDrainBytes = 1024 * 1024;
constexpr std::size_t kMaxConnections = 256;
constexpr auto kStopCheckInterval = std::chrono::milliseconds(200);

/// An owned file descriptor.
class Descriptor {
public:
    Descriptor() = default;
    explicit Descriptor(int fd) : fd_(fd) {}
    Descriptor(Descriptor&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}
    Descriptor& operator=(Descriptor&& other) noexcept {
        if (this != &other) reset(std::exchange(other.fd_, -1));
        return *this;
    }
    Descriptor(const Descriptor&) = delete;
    Descriptor& operator=(const Descriptor&) = delete;
    ~Descriptor() { reset(); }
    void reset(int fd = -1) {
        if (fd_ >= 0) ::close(fd_);
        fd_ = fd;
    }
    [[nodiscard]] int get() const { return fd_; }
    [[nodiscard]] bool valid() const { return fd_ >= 0; }

private:
    int fd_ = -1;
};

std::string_view content_type(std::string_view name) {
    const std::size_t dot = name.rfind('.');
    const std::string_view ext = dot == std::string_view::npos ? std::string_view() : name.substr(dot);
    if (ext == ".html") return "text/html; charset=utf-8";
    if (ext == ".js") return "text/javascript; charset=utf-8";
    if (ext == ".json") return "application/json";
    if (ext == ".csv") return "text/csv; charset=utf-8";
    if (ext == ".png") return "image/png";
    if (ext == ".f32" || ext == ".u32") return "application/octet-stream";
    return "text/plain; charset=utf-8";
}

std::string response_head(http::Status status, std::string_view type, std::uint64_t length,
                          std::string_view extra = {}) {
    return "HTTP/1.1 " + std::to_string(status.code) + " " + std::string(status.reason) +
           "\r\nContent-Type: " + std::string(type) + "\r\nContent-Length: " + std::to_string(length) +
           "\r\nCache-Control: no-store\r\nX-Content-Type-Options: nosniff\r\n" + std::string(extra) +
           "Connection: close\r\n\r\n";
}

/// One client connection: it reads the request head, sends one response, then reads and drops
/// what the client still sends until it closes (a close with unread input makes the kernel reset
/// the connection, and the reset can discard the answer before the client has read it).
struct Connection {
    enum class Phase { reading, sending, draining, closed };
    Descriptor socket;
    Phase phase = Phase::reading;
    Clock::time_point accepted;
    Clock::time_point deadline;  ///< reading: the request deadline; sending: the stall limit; draining: its end
    std::string received;        ///< the request head so far (at most kMaxHeadBytes + 1 bytes)
    std::string pending;         ///< response bytes not sent yet (head, or a whole error answer)
    std::size_t pending_sent = 0;
    Descriptor file;  ///< the body, sent with sendfile(2) after `pending`
    off_t file_offset = 0;
    std::uint64_t file_left = 0;
    std::size_t drained = 0;
};

class ViewServer {
public:
    ViewServer(int directory, int listener, std::size_t capacity)
        : directory_(directory), listener_(listener), capacity_(capacity) {}

    /// Until g_stop: poll, advance every connection that can move, expire deadlines, accept.
    void run() {
        std::vector<pollfd> fds;
        while (!g_stop.load()) {
            fds.clear();
            const bool accepting = Clock::now() >= accept_paused_until_;
            fds.push_back({listener_, short(accepting ? POLLIN : 0), 0});
            Clock::time_point wake = Clock::now() + kStopCheckInterval;
            for (const auto& c : connections_) {
                fds.push_back({c->socket.get(), short(c->phase == Connection::Phase::sending ? POLLOUT : POLLIN), 0});
                wake = std::min(wake, c->deadline);
            }
            const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(wake - Clock::now()).count();
            const int ready = ::poll(fds.data(), fds.size(), int(std::clamp<long long>(wait + 1, 0, 200)));
            if (ready < 0 && errno != EINTR)
                throw std::runtime_error(std::string("poll failed: ") + std::strerror(errno));
            const Clock::time_point now = Clock::now();
            for (std::size_t i = 0; ready > 0 && i < connections_.size(); ++i)
                if (fds[i + 1].revents != 0) advance(*connections_[i], fds[i + 1].revents, now);
            for (const auto& c : connections_)
                if (c->phase != Connection::Phase::closed && now >= c->deadline) expire(*c, now);
            std::erase_if(connections_, [](const auto& c) { return c->phase == Connection::Phase::closed; });
            if (ready > 0 && (fds[0].revents & POLLIN) != 0) accept_new(now);
        }
    }

private:
    void accept_new(Clock::time_point now) {
        for (int n = 0; n < 64; ++n) {  // the backlog, a batch at a time
            Descriptor socket(::accept4(listener_, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK));
            if (!socket.valid()) {
                // Out of descriptors (the process's or the system's): free one, or wait a little
                // rather than spin on a listener that stays readable. Else EAGAIN: none left.
                if (errno == EMFILE || errno == ENFILE) {
                    if (connections_.empty()) accept_paused_until_ = now + std::chrono::milliseconds(100);
                    else evict_one();
                }
                return;
            }
            if (connections_.size() >= capacity_) evict_one();
            auto c = std::make_unique<Connection>();
            c->socket = std::move(socket);
            c->accepted = now;
            c->deadline = now + kRequestDeadline;
            connections_.push_back(std::move(c));
        }
    }

    /// Makes room for a new connection: closes one that has been answered and is draining, else
    /// the oldest one still sending its request (slow or silent clients hold slots the longest),
    /// else the oldest one receiving its response.
    void evict_one() {
        const auto rank = [](const Connection& c) {
            return c.phase == Connection::Phase::draining ? 0 : c.phase == Connection::Phase::reading ? 1 : 2;
        };
        const auto victim =
            std::min_element(connections_.begin(), connections_.end(), [&](const auto& a, const auto& b) {
                return std::pair(rank(*a), a->accepted) < std::pair(rank(*b), b->accepted);
            });
        if (victim == connections_.end()) return;
        connections_.erase(victim);  // closes its socket and file
    }

    void advance(Connection& c, short events, Clock::time_point now) {
        switch (c.phase) {
            case Connection::Phase::reading:
                read_request(c, now);
                break;
            case Connection::Phase::sending:
                if ((events & (POLLERR | POLLHUP)) != 0 && (events & POLLOUT) == 0) close(c);
                else send_some(c, now);
                break;
            case Connection::Phase::draining:
                drain(c);
                break;
            case Connection::Phase::closed:
                break;
        }
    }

    void read_request(Connection& c, Clock::time_point now) {
        char buffer[4096];
        const std::size_t room = http::kMaxHeadBytes + 1 - c.received.size();
        const ssize_t n = ::recv(c.socket.get(), buffer, std::min(sizeof buffer, room), 0);
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return;
        if (n < 0) return close(c);
        const bool end_of_input = n == 0;
        c.received.append(buffer, std::size_t(n));
        const http::ParsedHead head = http::parse_request_head(c.received);
        switch (head.outcome) {
            case http::ParsedHead::Outcome::incomplete:
                if (!end_of_input) return;
                if (c.received.empty()) return close(c);             // connected and left: nothing to answer
                return answer_status(c, {400, "Bad Request"}, now);  // the client stopped mid-request
            case http::ParsedHead::Outcome::refused:
                return answer_status(c, head.status, now);
            case http::ParsedHead::Outcome::complete:
                break;
        }
        if (!http::is_loopback_host(head.host)) return answer_status(c, {421, "Misdirected Request"}, now);
        const http::Route route = http::route_request(head.method, head.target);
        if (route.status.code != 200) return answer_status(c, route.status, now);
        answer_file(c, route, now);
    }

    /// Opens `route.name` in the served directory: O_NOFOLLOW refuses a symbolic link, O_NONBLOCK
    /// keeps a FIFO from blocking the open, and fstat accepts regular files only. The name has no
    /// '/' (http::is_servable_name), so the file is an entry of the directory itself.
    void answer_file(Connection& c, const http::Route& route, Clock::time_point now) {
        Descriptor file(
            ::openat(directory_, route.name.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC | O_NOCTTY));
        struct stat info {};
        if (!file.valid() || ::fstat(file.get(), &info) != 0 || !S_ISREG(info.st_mode))
            return answer_status(c, {404, "Not Found"}, now);
        const auto size = std::uint64_t(info.st_size);
        c.pending = response_head({200, "OK"}, content_type(route.name), size);
        if (!route.head_only) {
            c.file = std::move(file);
            c.file_left = size;
        }
        start_sending(c, now);
    }

    void answer_status(Connection& c, http::Status status, Clock::time_point now) {
        const std::string body = std::to_string(status.code) + " " + std::string(status.reason) + "\n";
        c.pending = response_head(status, "text/plain; charset=utf-8", body.size(),
                                  status.code == 405 ? "Allow: GET, HEAD\r\n" : "") +
                    body;
        start_sending(c, now);
    }

    void start_sending(Connection& c, Clock::time_point now) {
        c.phase = Connection::Phase::sending;
        c.received = std::string();  // the head is answered: free it
        c.deadline = now + kSendStallLimit;
        send_some(c, now);
    }

    /// Sends until the socket is full; the stall limit restarts with every byte taken.
    void send_some(Connection& c, Clock::time_point now) {
        bool progress = false;
        while (c.pending_sent < c.pending.size()) {
            const ssize_t n = ::send(c.socket.get(), c.pending.data() + c.pending_sent,
                                     c.pending.size() - c.pending_sent, MSG_NOSIGNAL);
            if (n < 0 && errno == EINTR) continue;
            if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
            if (n <= 0) return close(c);  // the client went away
            c.pending_sent += std::size_t(n);
            progress = true;
        }
        while (c.pending_sent == c.pending.size() && c.file_left > 0) {
            const auto chunk = std::size_t(std::min<std::uint64_t>(c.file_left, 1 << 20));
            const ssize_t n = ::sendfile(c.socket.get(), c.file.get(), &c.file_offset, chunk);
            if (n < 0 && errno == EINTR) continue;
            if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
            if (n <= 0) return close(c);  // the client went away, or the file shrank under us
            c.file_left -= std::uint64_t(n);
            progress = true;
        }
        if (progress) c.deadline = now + kSendStallLimit;
        if (c.pending_sent == c.pending.size() && c.file_left == 0) {
            c.file.reset();
            c.pending = std::string();
            ::shutdown(c.socket.get(), SHUT_WR);  // the answer is complete: the client sees its end
            c.phase = Connection::Phase::draining;
            c.deadline = now + kDrainLimit;
            drain(c);
        }
    }

    void drain(Connection& c) {
        char buffer[4096];
        for (;;) {
            const ssize_t n = ::recv(c.socket.get(), buffer, sizeof buffer, 0);
            if (n < 0 && errno == EINTR) continue;
            if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;
            if (n <= 0) return close(c);  // the client closed: done
            c.drained += std::size_t(n);
            if (c.drained >= kMaxDrainBytes) return close(c);
        }
    }

    /// A deadline passed: a request still incomplete gets 408 (nothing, when nothing came), a
    /// stalled response or a drain that took too long ends the connection.
    void expire(Connection& c, Clock::time_point now) {
        if (c.phase == Connection::Phase::reading && !c.received.empty())
            answer_status(c, {408, "Request Timeout"}, now);
        else close(c);
    }

    static void close(Connection& c) {
        c.phase = Connection::Phase::closed;
        c.file.reset();
        c.socket.reset();
    }

    int directory_;
    int listener_;
    std::size_t capacity_;
    std::vector<std::unique_ptr<Connection>> connections_;
    Clock::time_point accept_paused_until_{};
};

/// Connections the process can hold: two descriptors each (socket, file), within RLIMIT_NOFILE.
std::size_t connection_capacity() {
    rlimit limit{};
    if (::getrlimit(RLIMIT_NOFILE, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return kMaxConnections;
    const auto spare = limit.rlim_cur > 64 ? (limit.rlim_cur - 64) / 2 : 1;
    return std::clamp<std::size_t>(spare, 1, kMaxConnections);
}

}  // namespace

void serve_directory(const std::filesystem::path& directory, int port, std::ostream& out) {
    Descriptor folder(::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
    if (!folder.valid())
        throw std::runtime_error("cannot open directory '" + directory.string() + "': " + std::strerror(errno));
    Descriptor listener(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0));
    if (!listener.valid()) throw std::runtime_error(std::string("cannot create a socket: ") + std::strerror(errno));
    const int yes = 1;
    ::setsockopt(listener.get(), SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);  // 127.0.0.1 only: never reachable from another host
    if (::bind(listener.get(), reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0 ||
        ::listen(listener.get(), 128) != 0)
        throw std::runtime_error("cannot listen on 127.0.0.1:" + std::to_string(port) + ": " + std::strerror(errno));
    socklen_t length = sizeof address;
    ::getsockname(listener.get(), reinterpret_cast<sockaddr*>(&address), &length);
    out << "penalty view: serving " << directory.string() << " at http://127.0.0.1:" << ntohs(address.sin_port)
        << "/ (Ctrl-C to stop)" << std::endl;

    g_stop.store(false);
    std::signal(SIGINT, on_stop_signal);
    std::signal(SIGTERM, on_stop_signal);
    std::signal(SIGPIPE, SIG_IGN);
    ViewServer(folder.get(), listener.get(), connection_capacity()).run();
    out << "penalty view: stopped" << std::endl;
}

}  // namespace penalty::apps
