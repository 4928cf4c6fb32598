#include "drone/transport/net.hpp"

#include <gtest/gtest.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

using namespace gs::transport;
using namespace std::chrono_literals;

namespace {

std::span<const std::uint8_t> bytes_of(const std::string& s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

std::string text_of(std::span<const std::uint8_t> b) {
    return {reinterpret_cast<const char*>(b.data()), b.size()};
}

UdpSocket bound_udp() {
    auto s = UdpSocket::bind(Endpoint::loopback(0));
    EXPECT_TRUE(s) << (s ? "" : s.error().message());
    return s ? std::move(*s) : UdpSocket{};
}

// Waits (bounded) for a timeout to elapse and returns how long the call took.
template <class F>
std::chrono::milliseconds timed(F&& f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() -
                                                                 t0);
}

}  // namespace

// ---- Endpoint -------------------------------------------------------------------------------

TEST(Endpoint, ParsesAndPrints) {
    auto e = Endpoint::parse("192.168.1.1:5556");
    ASSERT_TRUE(e);
    EXPECT_EQ(e->address, 0xC0A80101u);
    EXPECT_EQ(e->port, 5556);
    EXPECT_EQ(e->to_string(), "192.168.1.1:5556");
    EXPECT_EQ(*e, Endpoint::from_octets(192, 168, 1, 1, 5556));
    EXPECT_EQ(Endpoint::loopback(0).to_string(), "127.0.0.1:0");
    EXPECT_EQ(Endpoint::any(65535).to_string(), "0.0.0.0:65535");
    EXPECT_EQ(Endpoint::parse("255.255.255.255:65535")->address, 0xFFFFFFFFu);
}

TEST(Endpoint, RejectsMalformedText) {
    EXPECT_EQ(Endpoint::parse("192.168.1.1").error(), EndpointError::MissingPort);
    EXPECT_EQ(Endpoint::parse("192.168.1.1:").error(), EndpointError::BadPort);
    EXPECT_EQ(Endpoint::parse("192.168.1.1:65536").error(), EndpointError::BadPort);
    EXPECT_EQ(Endpoint::parse("192.168.1.1:-1").error(), EndpointError::BadPort);
    EXPECT_EQ(Endpoint::parse("192.168.1.1:55x").error(), EndpointError::BadPort);
    EXPECT_EQ(Endpoint::parse("192.168.1:80").error(), EndpointError::BadAddress);
    EXPECT_EQ(Endpoint::parse("192.168.1.1.1:80").error(), EndpointError::BadAddress);
    EXPECT_EQ(Endpoint::parse("192.168.1.256:80").error(), EndpointError::BadAddress);
    EXPECT_EQ(Endpoint::parse("192.168.01.1:80").error(), EndpointError::BadAddress);
    EXPECT_EQ(Endpoint::parse("192.168..1:80").error(), EndpointError::BadAddress);
    EXPECT_EQ(Endpoint::parse("localhost:80").error(), EndpointError::BadAddress);
    EXPECT_EQ(Endpoint::parse(":80").error(), EndpointError::BadAddress);
    EXPECT_FALSE(to_string(EndpointError::BadAddress).empty());
}

// ---- UDP ------------------------------------------------------------------------------------

TEST(UdpSocket, EchoReportsSourceEndpoint) {
    UdpSocket a = bound_udp();
    UdpSocket b = bound_udp();
    const auto a_ep = a.local_endpoint();
    const auto b_ep = b.local_endpoint();
    ASSERT_TRUE(a_ep && b_ep);
    EXPECT_EQ(a_ep->address, 0x7F000001u);
    EXPECT_NE(a_ep->port, 0);  // port 0 was replaced by an ephemeral one
    EXPECT_NE(a_ep->port, b_ep->port);

    auto sent = a.send_to("AT*COMWDG=1\r", *b_ep);
    ASSERT_TRUE(sent) << sent.error().message();
    EXPECT_EQ(*sent, 12u);

    std::vector<std::uint8_t> buf(64);
    auto got = b.recv_from(buf, 2000ms);
    ASSERT_TRUE(got) << got.error().message();
    EXPECT_EQ(text_of({buf.data(), got->size}), "AT*COMWDG=1\r");
    EXPECT_EQ(got->from, *a_ep);  // the drone answers navdata to exactly this address:port
    EXPECT_FALSE(got->truncated);

    // Echo back to the reported source.
    ASSERT_TRUE(b.send_to(std::span<const std::uint8_t>(buf.data(), got->size), got->from));
    auto back = a.recv_from(buf, 2000ms);
    ASSERT_TRUE(back);
    EXPECT_EQ(text_of({buf.data(), back->size}), "AT*COMWDG=1\r");
    EXPECT_EQ(back->from, *b_ep);
}

TEST(UdpSocket, EmptyDatagramIsReceivedAsZeroBytes) {
    UdpSocket a = bound_udp();
    UdpSocket b = bound_udp();
    ASSERT_TRUE(a.send_to(std::string_view{}, *b.local_endpoint()));
    std::vector<std::uint8_t> buf(8);
    auto got = b.recv_from(buf, 2000ms);
    ASSERT_TRUE(got);
    EXPECT_EQ(got->size, 0u);
}

TEST(UdpSocket, OversizedDatagramIsFlaggedTruncated) {
    UdpSocket a = bound_udp();
    UdpSocket b = bound_udp();
    ASSERT_TRUE(a.send_to(std::string(100, 'x'), *b.local_endpoint()));
    std::vector<std::uint8_t> buf(10);
    auto got = b.recv_from(buf, 2000ms);
    ASSERT_TRUE(got);
    EXPECT_EQ(got->size, 10u);
    EXPECT_TRUE(got->truncated);
}

TEST(UdpSocket, RecvTimeoutReturnsPromptly) {
    UdpSocket a = bound_udp();
    std::vector<std::uint8_t> buf(16);
    gs::Expected<UdpSocket::Received, NetError> got =
        gs::Unexpected{NetError{NetErrc::Socket, 0, ""}};
    const auto took = timed([&] { got = a.recv_from(buf, 50ms); });
    ASSERT_FALSE(got);
    EXPECT_EQ(got.error().code, NetErrc::Timeout);
    EXPECT_GE(took, 50ms);
    EXPECT_LT(took, 2000ms);
    EXPECT_FALSE(got.error().message().empty());

    const auto zero = timed([&] { got = a.recv_from(buf, 0ms); });
    EXPECT_EQ(got.error().code, NetErrc::Timeout);
    EXPECT_LT(zero, 2000ms);
}

TEST(UdpSocket, SetSendBufferLikeTheSdk) {
    UdpSocket a = bound_udp();
    auto r = a.set_send_buffer(256);
    EXPECT_TRUE(r) << r.error().message();
    UdpSocket b = bound_udp();
    // Small datagrams still go through with the tiny buffer.
    ASSERT_TRUE(a.send_to("AT*REF=1,290717696\r", *b.local_endpoint()));
    std::vector<std::uint8_t> buf(64);
    EXPECT_TRUE(b.recv_from(buf, 2000ms));
}

TEST(UdpSocket, BindingATakenPortFailsWithErrnoText) {
    UdpSocket a = bound_udp();
    auto b = UdpSocket::bind(*a.local_endpoint());
    ASSERT_FALSE(b);
    EXPECT_EQ(b.error().code, NetErrc::Bind);
    EXPECT_EQ(b.error().sys_errno, EADDRINUSE);
    EXPECT_NE(b.error().message().find(a.local_endpoint()->to_string()), std::string::npos);
    EXPECT_NE(b.error().message().find("in use"), std::string::npos) << b.error().message();
}

TEST(UdpSocket, ClosedSocketReportsClosed) {
    UdpSocket a;
    EXPECT_FALSE(a.is_open());
    std::vector<std::uint8_t> buf(4);
    EXPECT_EQ(a.recv_from(buf, 10ms).error().code, NetErrc::Closed);
    EXPECT_EQ(a.send_to("x", Endpoint::loopback(9)).error().code, NetErrc::Closed);
    EXPECT_EQ(a.local_endpoint().error().code, NetErrc::Closed);
    UdpSocket b = bound_udp();
    b.close();
    EXPECT_EQ(b.recv_from(buf, 10ms).error().code, NetErrc::Closed);
}

// ---- TCP ------------------------------------------------------------------------------------

struct TcpPair {
    TcpListener listener;
    TcpStream client;
    TcpStream server;
};

TcpPair connected_pair() {
    TcpPair p;
    auto l = TcpListener::listen(Endpoint::loopback(0));
    EXPECT_TRUE(l) << (l ? "" : l.error().message());
    if (!l) return p;
    p.listener = std::move(*l);
    auto c = TcpStream::connect(*p.listener.local_endpoint(), 2000ms);
    EXPECT_TRUE(c) << (c ? "" : c.error().message());
    if (!c) return p;
    p.client = std::move(*c);
    auto s = p.listener.accept(2000ms);
    EXPECT_TRUE(s) << (s ? "" : s.error().message());
    if (s) p.server = std::move(*s);
    return p;
}

TEST(TcpStream, ConnectAcceptReadWriteBothWays) {
    TcpPair p = connected_pair();
    ASSERT_TRUE(p.client.is_open() && p.server.is_open());
    EXPECT_EQ(*p.server.remote_endpoint(), *p.client.local_endpoint());
    EXPECT_EQ(*p.client.remote_endpoint(), *p.listener.local_endpoint());
    EXPECT_TRUE(p.client.set_no_delay(true));

    ASSERT_TRUE(p.server.write_all("PaVE....", 2000ms));
    std::vector<std::uint8_t> buf(64);
    std::string got;
    while (got.size() < 8) {
        auto n = p.client.read_some(buf, 2000ms);
        ASSERT_TRUE(n) << n.error().message();
        got += text_of({buf.data(), *n});
    }
    EXPECT_EQ(got, "PaVE....");

    ASSERT_TRUE(p.client.write_all(bytes_of("\x01\x00\x00\x00"), 2000ms));
    auto n = p.server.read_some(buf, 2000ms);
    ASSERT_TRUE(n);
    EXPECT_EQ(text_of({buf.data(), *n}), std::string("\x01"));
}

TEST(TcpStream, LargeWriteArrivesComplete) {
    TcpPair p = connected_pair();
    std::string big(4 << 20, '\0');
    for (std::size_t i = 0; i < big.size(); ++i) big[i] = static_cast<char>(i * 31 + (i >> 9));
    std::string received;
    std::thread reader([&] {
        std::vector<std::uint8_t> buf(65536);
        while (received.size() < big.size()) {
            auto n = p.server.read_some(buf, 5000ms);
            if (!n) return;
            received += text_of({buf.data(), *n});
        }
    });
    auto w = p.client.write_all(big, 10000ms);
    reader.join();
    ASSERT_TRUE(w) << w.error().message();
    EXPECT_EQ(received.size(), big.size());
    EXPECT_TRUE(received == big);
}

TEST(TcpStream, ReadTimeoutReturnsPromptly) {
    TcpPair p = connected_pair();
    std::vector<std::uint8_t> buf(16);
    gs::Expected<std::size_t, NetError> n = std::size_t{0};
    const auto took = timed([&] { n = p.client.read_some(buf, 50ms); });
    ASSERT_FALSE(n);
    EXPECT_EQ(n.error().code, NetErrc::Timeout);
    EXPECT_GE(took, 50ms);
    EXPECT_LT(took, 2000ms);
}

TEST(TcpStream, WriteTimesOutWhenPeerDoesNotRead) {
    TcpPair p = connected_pair();
    const std::string chunk(64 << 20, 'x');  // far more than loopback socket buffers hold
    gs::Expected<void, NetError> w;
    const auto took = timed([&] { w = p.client.write_all(chunk, 200ms); });
    ASSERT_FALSE(w);
    EXPECT_EQ(w.error().code, NetErrc::Timeout);
    EXPECT_LT(took, 5000ms);
}

TEST(TcpStream, PeerCloseIsReportedAsClosed) {
    TcpPair p = connected_pair();
    ASSERT_TRUE(p.server.write_all("bye", 2000ms));
    p.server.close();
    std::vector<std::uint8_t> buf(16);
    std::string got;
    gs::Expected<std::size_t, NetError> n = std::size_t{0};
    while ((n = p.client.read_some(buf, 2000ms))) got += text_of({buf.data(), *n});
    EXPECT_EQ(got, "bye");  // data before the close is still delivered
    EXPECT_EQ(n.error().code, NetErrc::Closed);
}

TEST(TcpStream, ShutdownWriteSignalsEndOfStream) {
    TcpPair p = connected_pair();
    p.client.shutdown_write();
    std::vector<std::uint8_t> buf(16);
    auto n = p.server.read_some(buf, 2000ms);
    ASSERT_FALSE(n);
    EXPECT_EQ(n.error().code, NetErrc::Closed);
    // The other direction still works.
    ASSERT_TRUE(p.server.write_all("ok", 2000ms));
    auto m = p.client.read_some(buf, 2000ms);
    ASSERT_TRUE(m);
    EXPECT_EQ(text_of({buf.data(), *m}), "ok");
}

TEST(TcpStream, ShutdownFromAnotherThreadWakesABlockedRead) {
    TcpPair p = connected_pair();
    gs::Expected<std::size_t, NetError> n = std::size_t{0};
    std::chrono::milliseconds took{};
    std::thread reader([&] {
        std::vector<std::uint8_t> buf(16);
        took = timed([&] { n = p.client.read_some(buf, 30000ms); });
    });
    p.client.shutdown();  // whether the read started yet or not, it ends with Closed
    reader.join();
    ASSERT_FALSE(n);
    EXPECT_EQ(n.error().code, NetErrc::Closed);
    EXPECT_LT(took, 10000ms);
}

TEST(TcpStream, ConnectToClosedPortFailsClearly) {
    Endpoint closed;
    {
        auto l = TcpListener::listen(Endpoint::loopback(0));
        ASSERT_TRUE(l);
        closed = *l->local_endpoint();
    }  // listener closed: nothing listens on that port now
    auto c = TcpStream::connect(closed, 2000ms);
    ASSERT_FALSE(c);
    EXPECT_EQ(c.error().code, NetErrc::Connect);
    EXPECT_EQ(c.error().sys_errno, ECONNREFUSED);
    const std::string msg = c.error().message();
    EXPECT_NE(msg.find("connect " + closed.to_string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("refused"), std::string::npos) << msg;
}

TEST(TcpListener, AcceptTimeoutReturnsPromptly) {
    auto l = TcpListener::listen(Endpoint::loopback(0));
    ASSERT_TRUE(l);
    gs::Expected<TcpStream, NetError> s = gs::Unexpected{NetError{NetErrc::Socket, 0, ""}};
    const auto took = timed([&] { s = l->accept(50ms); });
    ASSERT_FALSE(s);
    EXPECT_EQ(s.error().code, NetErrc::Timeout);
    EXPECT_GE(took, 50ms);
    EXPECT_LT(took, 2000ms);
}

TEST(TcpListener, ListeningOnATakenPortFails) {
    auto a = TcpListener::listen(Endpoint::loopback(0));
    ASSERT_TRUE(a);
    auto b = TcpListener::listen(*a->local_endpoint());
    ASSERT_FALSE(b);
    EXPECT_EQ(b.error().code, NetErrc::Bind);
    EXPECT_EQ(b.error().sys_errno, EADDRINUSE);
}

TEST(TcpStream, NotOpenReportsClosed) {
    TcpStream s;
    std::vector<std::uint8_t> buf(4);
    EXPECT_EQ(s.read_some(buf, 10ms).error().code, NetErrc::Closed);
    EXPECT_EQ(s.write_all("x", 10ms).error().code, NetErrc::Closed);
    EXPECT_EQ(s.remote_endpoint().error().code, NetErrc::Closed);
    TcpListener l;
    EXPECT_EQ(l.accept(10ms).error().code, NetErrc::Closed);
}

TEST(NetError, MessagesNameTheOperationAndErrno) {
    const NetError e{NetErrc::Connect, ECONNREFUSED, "connect 127.0.0.1:5555"};
    EXPECT_NE(e.message().find("connect 127.0.0.1:5555: "), std::string::npos);
    EXPECT_GT(e.message().size(), std::string("connect 127.0.0.1:5555: ").size());
    const NetError t{NetErrc::Timeout, 0, ""};
    EXPECT_EQ(t.message(), "timed out");
}
