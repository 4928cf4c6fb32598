#pragma once
// Thin RAII wrappers over POSIX IPv4 sockets for the drone link and the virtual drone. Every
// socket is non-blocking and every call that could wait takes a timeout (poll underneath), so a
// thread looping on them notices a stop flag within one timeout. Errors are values (NetError with
// the errno text), never exceptions. The protocol codecs never see these: they get bytes.

#include "drone/core/expected.hpp"
#include "drone/transport/endpoint.hpp"

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <variant>

namespace gs::transport {

using Millis = std::chrono::milliseconds;

enum class NetErrc {
    Socket,   // socket() or a socket option failed
    Bind,     // bind() failed (address in use, not local ...)
    Listen,   // listen() failed
    Accept,   // accept() failed
    Connect,  // connect failed or was refused
    Send,     // send failed
    Recv,     // receive failed
    Timeout,  // nothing happened within the timeout
    Closed,   // the peer closed the connection, or the socket is not open
};
[[nodiscard]] std::string_view to_string(NetErrc c);

struct NetError {
    NetErrc code;
    int sys_errno = 0;    // errno of the failing call, 0 when not a system error
    std::string context;  // what was being done, e.g. "connect 127.0.0.1:5555"
    // "connect 127.0.0.1:5555: Connection refused"
    [[nodiscard]] std::string message() const;
};

// Owns one file descriptor; closes it on destruction. Move-only.
class Fd {
public:
    Fd() = default;
    explicit Fd(int fd) : fd_(fd) {}
    Fd(Fd&& o) noexcept : fd_(o.release()) {}
    Fd& operator=(Fd&& o) noexcept;
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    ~Fd() { reset(); }

    [[nodiscard]] int get() const { return fd_; }
    [[nodiscard]] bool valid() const { return fd_ >= 0; }
    int release() {
        const int f = fd_;
        fd_ = -1;
        return f;
    }
    void reset();

private:
    int fd_ = -1;
};

class UdpSocket {
public:
    struct Received {
        std::size_t size = 0;    // bytes written into the buffer
        Endpoint from;           // source address and port
        bool truncated = false;  // the datagram was larger than the buffer; the rest is lost
    };

    UdpSocket() = default;  // not open
    // Binds to `local` (port 0 = an ephemeral port; read it back with local_endpoint()).
    [[nodiscard]] static Expected<UdpSocket, NetError> bind(const Endpoint& local);

    [[nodiscard]] bool is_open() const { return fd_.valid(); }
    [[nodiscard]] Expected<Endpoint, NetError> local_endpoint() const;
    // Sends one datagram. Waits up to `timeout` for buffer space (a small SO_SNDBUF can fill).
    [[nodiscard]] Expected<std::size_t, NetError> send_to(std::span<const std::uint8_t> bytes,
                                                          const Endpoint& to,
                                                          Millis timeout = Millis{100});
    [[nodiscard]] Expected<std::size_t, NetError> send_to(std::string_view text, const Endpoint& to,
                                                          Millis timeout = Millis{100});
    // Waits up to `timeout` for one datagram (NetErrc::Timeout when none came).
    [[nodiscard]] Expected<Received, NetError> recv_from(std::span<std::uint8_t> buf,
                                                         Millis timeout);
    // SO_SNDBUF (the SDK uses 256 on the AT socket to keep latency low).
    [[nodiscard]] Expected<void, NetError> set_send_buffer(int bytes);
    void close() { fd_.reset(); }
    [[nodiscard]] int native_handle() const { return fd_.get(); }

private:
    explicit UdpSocket(Fd fd) : fd_(std::move(fd)) {}
    Fd fd_;
};

class TcpStream {
public:
    TcpStream() = default;  // not open
    // Connects within `timeout`; a refused or unreachable peer is NetErrc::Connect with errno.
    [[nodiscard]] static Expected<TcpStream, NetError> connect(const Endpoint& remote,
                                                               Millis timeout);

    [[nodiscard]] bool is_open() const { return fd_.valid(); }
    [[nodiscard]] Expected<Endpoint, NetError> local_endpoint() const;
    [[nodiscard]] Expected<Endpoint, NetError> remote_endpoint() const;
    // Reads what is available (at least 1 byte) within `timeout`. The peer closing the stream is
    // NetErrc::Closed; no data in time is NetErrc::Timeout.
    [[nodiscard]] Expected<std::size_t, NetError> read_some(std::span<std::uint8_t> buf,
                                                            Millis timeout);
    // Writes every byte within `timeout` overall (NetErrc::Timeout if the peer does not drain).
    [[nodiscard]] Expected<void, NetError> write_all(std::span<const std::uint8_t> bytes,
                                                     Millis timeout);
    [[nodiscard]] Expected<void, NetError> write_all(std::string_view text, Millis timeout);
    // TCP_NODELAY: send small writes at once (control channel).
    [[nodiscard]] Expected<void, NetError> set_no_delay(bool on);
    // Ends the sending direction (the peer reads end of stream), keeps reading possible.
    void shutdown_write();
    // Ends both directions; a read_some blocked in another thread returns promptly.
    void shutdown();
    void close() { fd_.reset(); }
    [[nodiscard]] int native_handle() const { return fd_.get(); }

private:
    friend class TcpListener;
    explicit TcpStream(Fd fd) : fd_(std::move(fd)) {}
    Fd fd_;
};

class TcpListener {
public:
    TcpListener() = default;  // not open
    // Binds (SO_REUSEADDR, so a restarted virtual drone can take its port back) and listens.
    [[nodiscard]] static Expected<TcpListener, NetError> listen(const Endpoint& local,
                                                                int backlog = 4);

    [[nodiscard]] bool is_open() const { return fd_.valid(); }
    [[nodiscard]] Expected<Endpoint, NetError> local_endpoint() const;
    // Waits up to `timeout` for one connection (NetErrc::Timeout when none came).
    [[nodiscard]] Expected<TcpStream, NetError> accept(Millis timeout);
    void close() { fd_.reset(); }
    [[nodiscard]] int native_handle() const { return fd_.get(); }

private:
    explicit TcpListener(Fd fd) : fd_(std::move(fd)) {}
    Fd fd_;
};

}  // namespace gs::transport
