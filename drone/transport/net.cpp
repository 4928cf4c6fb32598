#include "drone/transport/net.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace gs::transport {

std::string_view to_string(NetErrc c) {
    switch (c) {
        case NetErrc::Socket:
            return "socket error";
        case NetErrc::Bind:
            return "bind failed";
        case NetErrc::Listen:
            return "listen failed";
        case NetErrc::Accept:
            return "accept failed";
        case NetErrc::Connect:
            return "connect failed";
        case NetErrc::Send:
            return "send failed";
        case NetErrc::Recv:
            return "receive failed";
        case NetErrc::Timeout:
            return "timed out";
        case NetErrc::Closed:
            return "connection closed";
    }
    return "unknown network error";
}

namespace {

// strerror_r comes in a GNU (char*) and an XSI (int) flavour; accept both.
[[maybe_unused]] std::string strerror_result(char* r, const char*) {
    return r;
}
[[maybe_unused]] std::string strerror_result(int r, const char* buf) {
    return r == 0 ? std::string(buf) : std::string("unknown error");
}

std::string errno_text(int e) {
    char buf[256] = {};
    return strerror_result(strerror_r(e, buf, sizeof buf), buf);
}

// Reads errno before anything else can touch it; `context` must not be built from a temporary
// that allocates after the failing call (use the overload with a saved errno for that).
NetError sys_error(NetErrc code, std::string_view context) {
    const int err = errno;
    return NetError{code, err, std::string(context)};
}

NetError sys_error(NetErrc code, std::string_view context, int err) {
    return NetError{code, err, std::string(context)};
}

NetError plain_error(NetErrc code, std::string context) {
    return NetError{code, 0, std::move(context)};
}

NetError not_open(std::string_view what) {
    return plain_error(NetErrc::Closed, std::string(what) + ": socket not open");
}

sockaddr_in to_sockaddr(const Endpoint& e) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(e.port);
    a.sin_addr.s_addr = htonl(e.address);
    return a;
}

Endpoint from_sockaddr(const sockaddr_in& a) {
    return {ntohl(a.sin_addr.s_addr), ntohs(a.sin_port)};
}

using SteadyTime = std::chrono::steady_clock::time_point;

SteadyTime deadline_after(Millis timeout) {
    return std::chrono::steady_clock::now() + timeout;
}

// Waits until `fd` is ready for `events` or the deadline passes. Error/hang-up conditions count
// as ready: the following call reports them with its own errno.
enum class Wait { Ready, Timeout, Error };
Wait wait_for(int fd, short events, SteadyTime deadline) {
    while (true) {
        const auto left = std::chrono::ceil<Millis>(deadline - std::chrono::steady_clock::now());
        const int ms =
            left.count() <= 0 ? 0 : static_cast<int>(std::min<Millis::rep>(left.count(), 1 << 30));
        pollfd p{fd, events, 0};
        const int r = ::poll(&p, 1, ms);
        if (r > 0) return Wait::Ready;
        if (r == 0) return Wait::Timeout;
        if (errno != EINTR) return Wait::Error;
    }
}

std::string timeout_context(std::string_view what, Millis timeout) {
    return std::string(what) + ": nothing within " + std::to_string(timeout.count()) + " ms";
}

bool would_block(int e) {
#if EAGAIN == EWOULDBLOCK
    return e == EAGAIN;
#else
    return e == EAGAIN || e == EWOULDBLOCK;
#endif
}

bool peer_gone(int e) {
    return e == ECONNRESET || e == EPIPE || e == ENOTCONN;
}

Expected<Endpoint, NetError> sock_name(int fd, bool peer) {
    const char* what = peer ? "getpeername" : "getsockname";
    if (fd < 0) return Unexpected{not_open(what)};
    sockaddr_in a{};
    socklen_t len = sizeof a;
    const int r = peer ? ::getpeername(fd, reinterpret_cast<sockaddr*>(&a), &len)
                       : ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
    if (r != 0) return Unexpected{sys_error(NetErrc::Socket, what)};
    return from_sockaddr(a);
}

Expected<Fd, NetError> open_socket(int type) {
    Fd fd(::socket(AF_INET, type | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
    if (!fd.valid()) return Unexpected{sys_error(NetErrc::Socket, "socket")};
    return fd;
}

Expected<void, NetError> bind_to(const Fd& fd, const Endpoint& local) {
    const sockaddr_in a = to_sockaddr(local);
    if (::bind(fd.get(), reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0) {
        const int err = errno;
        return Unexpected{sys_error(NetErrc::Bind, "bind " + local.to_string(), err)};
    }
    return {};
}

Expected<void, NetError> set_int_option(int fd, int level, int name, int value, const char* what) {
    if (fd < 0) return Unexpected{not_open(what)};
    if (::setsockopt(fd, level, name, &value, sizeof value) != 0) {
        return Unexpected{sys_error(NetErrc::Socket, what)};
    }
    return {};
}

}  // namespace

std::string NetError::message() const {
    std::string m = context.empty() ? std::string(to_string(code)) : context;
    if (sys_errno != 0) m += ": " + errno_text(sys_errno);
    return m;
}

// ---- Fd -------------------------------------------------------------------------------------

Fd& Fd::operator=(Fd&& o) noexcept {
    if (this != &o) {
        reset();
        fd_ = o.release();
    }
    return *this;
}

void Fd::reset() {
    if (fd_ >= 0) ::close(fd_);  // the descriptor is gone even when close reports an error
    fd_ = -1;
}

// ---- UdpSocket ------------------------------------------------------------------------------

Expected<UdpSocket, NetError> UdpSocket::bind(const Endpoint& local) {
    GS_TRY_ASSIGN(auto fd, open_socket(SOCK_DGRAM));
    GS_TRY(bind_to(fd, local));
    return UdpSocket(std::move(fd));
}

Expected<Endpoint, NetError> UdpSocket::local_endpoint() const {
    return sock_name(fd_.get(), false);
}

Expected<std::size_t, NetError> UdpSocket::send_to(std::span<const std::uint8_t> bytes,
                                                   const Endpoint& to, Millis timeout) {
    if (!fd_.valid()) return Unexpected{not_open("send_to")};
    const sockaddr_in a = to_sockaddr(to);
    const auto deadline = deadline_after(timeout);
    while (true) {
        const ssize_t n = ::sendto(fd_.get(), bytes.data(), bytes.size(), MSG_NOSIGNAL,
                                   reinterpret_cast<const sockaddr*>(&a), sizeof a);
        if (n >= 0) return static_cast<std::size_t>(n);
        if (errno == EINTR) continue;
        if (!would_block(errno)) {
            const int err = errno;
            return Unexpected{sys_error(NetErrc::Send, "send_to " + to.to_string(), err)};
        }
        switch (wait_for(fd_.get(), POLLOUT, deadline)) {
            case Wait::Ready:
                break;
            case Wait::Timeout:
                return Unexpected{plain_error(
                    NetErrc::Timeout, timeout_context("send_to " + to.to_string(), timeout))};
            case Wait::Error:
                return Unexpected{sys_error(NetErrc::Send, "poll")};
        }
    }
}

Expected<std::size_t, NetError> UdpSocket::send_to(std::string_view text, const Endpoint& to,
                                                   Millis timeout) {
    return send_to(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()),
                                                 text.size()),
                   to, timeout);
}

Expected<UdpSocket::Received, NetError> UdpSocket::recv_from(std::span<std::uint8_t> buf,
                                                             Millis timeout) {
    if (!fd_.valid()) return Unexpected{not_open("recv_from")};
    const auto deadline = deadline_after(timeout);
    while (true) {
        sockaddr_in a{};
        iovec iov{buf.data(), buf.size()};
        msghdr msg{};
        msg.msg_name = &a;
        msg.msg_namelen = sizeof a;
        msg.msg_iov = &iov;
        msg.msg_iovlen = 1;
        const ssize_t n = ::recvmsg(fd_.get(), &msg, 0);
        if (n >= 0) {
            return Received{static_cast<std::size_t>(n), from_sockaddr(a),
                            (msg.msg_flags & MSG_TRUNC) != 0};
        }
        if (errno == EINTR) continue;
        if (!would_block(errno)) return Unexpected{sys_error(NetErrc::Recv, "recv_from")};
        switch (wait_for(fd_.get(), POLLIN, deadline)) {
            case Wait::Ready:
                break;
            case Wait::Timeout:
                return Unexpected{
                    plain_error(NetErrc::Timeout, timeout_context("recv_from", timeout))};
            case Wait::Error:
                return Unexpected{sys_error(NetErrc::Recv, "poll")};
        }
    }
}

Expected<void, NetError> UdpSocket::set_send_buffer(int bytes) {
    return set_int_option(fd_.get(), SOL_SOCKET, SO_SNDBUF, bytes, "setsockopt SO_SNDBUF");
}

// ---- TcpStream ------------------------------------------------------------------------------

Expected<TcpStream, NetError> TcpStream::connect(const Endpoint& remote, Millis timeout) {
    GS_TRY_ASSIGN(auto fd, open_socket(SOCK_STREAM));
    const std::string what = "connect " + remote.to_string();
    const sockaddr_in a = to_sockaddr(remote);
    int r = ::connect(fd.get(), reinterpret_cast<const sockaddr*>(&a), sizeof a);
    if (r != 0 && errno != EINPROGRESS && errno != EINTR) {
        return Unexpected{sys_error(NetErrc::Connect, what)};
    }
    if (r != 0) {
        switch (wait_for(fd.get(), POLLOUT, deadline_after(timeout))) {
            case Wait::Ready:
                break;
            case Wait::Timeout:
                return Unexpected{plain_error(NetErrc::Timeout, timeout_context(what, timeout))};
            case Wait::Error:
                return Unexpected{sys_error(NetErrc::Connect, "poll")};
        }
        int err = 0;
        socklen_t len = sizeof err;
        if (::getsockopt(fd.get(), SOL_SOCKET, SO_ERROR, &err, &len) != 0) {
            return Unexpected{sys_error(NetErrc::Connect, what)};
        }
        if (err != 0) return Unexpected{sys_error(NetErrc::Connect, what, err)};
    }
    return TcpStream(std::move(fd));
}

Expected<Endpoint, NetError> TcpStream::local_endpoint() const {
    return sock_name(fd_.get(), false);
}

Expected<Endpoint, NetError> TcpStream::remote_endpoint() const {
    return sock_name(fd_.get(), true);
}

Expected<std::size_t, NetError> TcpStream::read_some(std::span<std::uint8_t> buf, Millis timeout) {
    if (!fd_.valid()) return Unexpected{not_open("read")};
    if (buf.empty()) return std::size_t{0};
    const auto deadline = deadline_after(timeout);
    while (true) {
        const ssize_t n = ::recv(fd_.get(), buf.data(), buf.size(), 0);
        if (n > 0) return static_cast<std::size_t>(n);
        if (n == 0) return Unexpected{plain_error(NetErrc::Closed, "read: peer closed the stream")};
        if (errno == EINTR) continue;
        if (peer_gone(errno)) return Unexpected{sys_error(NetErrc::Closed, "read")};
        if (!would_block(errno)) return Unexpected{sys_error(NetErrc::Recv, "read")};
        switch (wait_for(fd_.get(), POLLIN, deadline)) {
            case Wait::Ready:
                break;
            case Wait::Timeout:
                return Unexpected{plain_error(NetErrc::Timeout, timeout_context("read", timeout))};
            case Wait::Error:
                return Unexpected{sys_error(NetErrc::Recv, "poll")};
        }
    }
}

Expected<void, NetError> TcpStream::write_all(std::span<const std::uint8_t> bytes, Millis timeout) {
    if (!fd_.valid()) return Unexpected{not_open("write")};
    const auto deadline = deadline_after(timeout);
    while (!bytes.empty()) {
        const ssize_t n = ::send(fd_.get(), bytes.data(), bytes.size(), MSG_NOSIGNAL);
        if (n > 0) {
            bytes = bytes.subspan(static_cast<std::size_t>(n));
            continue;
        }
        if (n < 0 && errno == EINTR) continue;
        if (n < 0 && peer_gone(errno)) return Unexpected{sys_error(NetErrc::Closed, "write")};
        if (n < 0 && !would_block(errno)) return Unexpected{sys_error(NetErrc::Send, "write")};
        switch (wait_for(fd_.get(), POLLOUT, deadline)) {
            case Wait::Ready:
                break;
            case Wait::Timeout:
                return Unexpected{plain_error(
                    NetErrc::Timeout,
                    timeout_context("write (" + std::to_string(bytes.size()) + " bytes left)",
                                    timeout))};
            case Wait::Error:
                return Unexpected{sys_error(NetErrc::Send, "poll")};
        }
    }
    return {};
}

Expected<void, NetError> TcpStream::write_all(std::string_view text, Millis timeout) {
    return write_all(std::span<const std::uint8_t>(
                         reinterpret_cast<const std::uint8_t*>(text.data()), text.size()),
                     timeout);
}

Expected<void, NetError> TcpStream::set_no_delay(bool on) {
    return set_int_option(fd_.get(), IPPROTO_TCP, TCP_NODELAY, on ? 1 : 0,
                          "setsockopt TCP_NODELAY");
}

void TcpStream::shutdown_write() {
    if (fd_.valid()) ::shutdown(fd_.get(), SHUT_WR);
}

void TcpStream::shutdown() {
    if (fd_.valid()) ::shutdown(fd_.get(), SHUT_RDWR);
}

// ---- TcpListener ----------------------------------------------------------------------------

Expected<TcpListener, NetError> TcpListener::listen(const Endpoint& local, int backlog) {
    GS_TRY_ASSIGN(auto fd, open_socket(SOCK_STREAM));
    GS_TRY(set_int_option(fd.get(), SOL_SOCKET, SO_REUSEADDR, 1, "setsockopt SO_REUSEADDR"));
    GS_TRY(bind_to(fd, local));
    if (::listen(fd.get(), backlog) != 0) {
        const int err = errno;
        return Unexpected{sys_error(NetErrc::Listen, "listen " + local.to_string(), err)};
    }
    return TcpListener(std::move(fd));
}

Expected<Endpoint, NetError> TcpListener::local_endpoint() const {
    return sock_name(fd_.get(), false);
}

Expected<TcpStream, NetError> TcpListener::accept(Millis timeout) {
    if (!fd_.valid()) return Unexpected{not_open("accept")};
    const auto deadline = deadline_after(timeout);
    while (true) {
        Fd fd(::accept4(fd_.get(), nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC));
        if (fd.valid()) return TcpStream(std::move(fd));
        // A connection reset before we took it is the client's problem, not the listener's.
        if (errno == EINTR || errno == ECONNABORTED) continue;
        if (!would_block(errno)) return Unexpected{sys_error(NetErrc::Accept, "accept")};
        switch (wait_for(fd_.get(), POLLIN, deadline)) {
            case Wait::Ready:
                break;
            case Wait::Timeout:
                return Unexpected{
                    plain_error(NetErrc::Timeout, timeout_context("accept", timeout))};
            case Wait::Error:
                return Unexpected{sys_error(NetErrc::Accept, "poll")};
        }
    }
}

}  // namespace gs::transport
