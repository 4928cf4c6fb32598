#include "drone/sim/virtual_drone.hpp"

#include "drone/protocol/pave.hpp"
#include "drone/transport/net.hpp"
#include "drone/video/h264_encoder.hpp"

#include <poll.h>
#include <sys/socket.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <optional>

namespace gs::sim {
namespace {

// The shipped default (assets/calibration), so the ground station's default camera model is the
// one the images were rendered with; the compiled-in copy when the asset is unreadable.
CameraCalibration camera_calibration(CameraId id) {
    auto c = default_calibration(id);
    return c ? *c : builtin_calibration(id);
}
}  // namespace

const Clock& VirtualDrone::clock() const {
    return options_.clock ? *options_.clock : SteadyClock::instance();
}

bool VirtualDrone::wait_reached(TimeNs t, std::chrono::milliseconds timeout) const {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
        const bool core = core_time_.load() >= t;
        const bool video = !video_client_.load() || video_next_due_.load() > t;
        if (core && video) return true;
        if (!running_) return false;
        std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    return false;
}

struct VirtualDrone::Sockets {
    transport::UdpSocket at, navdata;
    transport::TcpListener video, control;
    std::optional<Renderer> front;  // built before the video port is served
};

VirtualDrone::VirtualDrone(VirtualDroneOptions options) : options_(std::move(options)) {
    if (!options_.scene.target_id.empty())
        target_ = find_obstacle(options_.scene, options_.scene.target_id);
}

record::TruthScene VirtualDrone::truth_scene() const {
    const Scene& s = options_.scene;
    return {s.scenario, s.name, s.target_id, s.description};
}

record::TruthSample VirtualDrone::truth_sample() const {
    const GroundTruth g = ground_truth();
    const Pose& p = g.pose;
    return {g.t_ns, {p.x_m, p.y_m, p.z_m, p.roll_deg, p.pitch_deg, p.yaw_deg}};
}

std::optional<record::TargetOffset> VirtualDrone::target_offset(const record::TruthPose& p) const {
    if (!target_) return std::nullopt;
    const ObstacleHit hit = obstacle_relative(options_.scene, *target_, p.x_m, p.y_m, p.yaw_deg);
    return record::TargetOffset{hit.distance_m, hit.lateral_m};
}

std::vector<record::TruthCollision> VirtualDrone::truth_collisions() const {
    std::vector<record::TruthCollision> out;
    for (const CollisionEvent& e : status().collisions)
        out.push_back({e.t_ns,
                       e.crash,
                       to_string(e.kind),
                       e.what,
                       {e.x_m, e.y_m, e.z_m, 0, 0, 0},
                       e.speed_mps,
                       e.approach_mps});
    return out;
}

VirtualDrone::~VirtualDrone() {
    stop();
}

Expected<void, StartError> VirtualDrone::start() {
    using enum StartError::Code;
    if (running_) return {};
    auto ep = [&](std::uint16_t port) -> Expected<transport::Endpoint, StartError> {
        auto e = transport::Endpoint::parse(options_.bind_address + ":" + std::to_string(port));
        if (!e)
            return Unexpected(
                StartError{BadBindAddress, "bad bind address '" + options_.bind_address + "'"});
        return *e;
    };
    auto s = std::make_unique<Sockets>();
    GS_TRY_ASSIGN(auto at_ep, ep(options_.at_port));
    auto at = transport::UdpSocket::bind(at_ep);
    if (!at) return Unexpected(StartError{Socket, "AT port: " + at.error().message()});
    auto nav = transport::UdpSocket::bind(*ep(options_.navdata_port));
    if (!nav) return Unexpected(StartError{Socket, "navdata port: " + nav.error().message()});
    auto video = transport::TcpListener::listen(*ep(options_.video_port));
    if (!video) return Unexpected(StartError{Socket, "video port: " + video.error().message()});
    auto control = transport::TcpListener::listen(*ep(options_.control_port));
    if (!control)
        return Unexpected(StartError{Socket, "control port: " + control.error().message()});
    s->at = std::move(*at);
    s->navdata = std::move(*nav);
    s->video = std::move(*video);
    s->control = std::move(*control);
    ports_[0] = s->at.local_endpoint()->port;
    ports_[1] = s->navdata.local_endpoint()->port;
    ports_[2] = s->video.local_endpoint()->port;
    ports_[3] = s->control.local_endpoint()->port;
    if (options_.video) {
        // Building a renderer inverts the lens model for every pixel: do it before serving.
        auto front = Renderer::create(options_.scene, camera_calibration(CameraId::Front),
                                      CameraKind::Front);
        if (!front)
            return Unexpected(StartError{Renderer, "renderer: " + to_string(front.error())});
        s->front.emplace(std::move(*front));
    }
    sockets_ = std::move(s);

    faults_.reopen();
    video_stalls_.reopen();
    video_resets_.reopen();
    dumps_.reopen();
    running_ = true;
    threads_.emplace_back([this] { core_loop(); });
    if (options_.video) threads_.emplace_back([this] { video_loop(); });
    threads_.emplace_back([this] { control_loop(); });
    return {};
}

void VirtualDrone::stop() {
    if (!running_.exchange(false)) return;
    faults_.close();
    dumps_.close();
    for (auto& t : threads_) t.join();
    threads_.clear();
    sockets_.reset();
}

void VirtualDrone::core_loop() {
    DroneCoreOptions co = options_.core;
    co.video_bitrate_kbps = options_.bitrate_bps / 1000;  // what it reports is what it streams
    co.start = options_.scene.start;
    co.autopilot = options_.scene.autopilot;
    co.autopilot_enabled = options_.autopilot;
    if (!options_.autopilot) co.start.z_m = 0;  // a pilot takes off from the ground
    if (options_.collisions) co.collider.emplace(options_.scene, options_.collision);
    DroneCore core(co);
    std::vector<OutDatagram> out;
    std::array<std::uint8_t, 2048> buf{};
    std::uint64_t report_gen = 0;
    VideoReport report;
    TimeNs last_status = 0;
    std::array<pollfd, 2> fds{};
    fds[0].fd = sockets_->at.native_handle();
    fds[1].fd = sockets_->navdata.native_handle();

    while (running_) {
        fds[0].events = fds[1].events = POLLIN;
        fds[0].revents = fds[1].revents = 0;
        ::poll(fds.data(), fds.size(), 1);
        const TimeNs now = clock().now_ns();
        // Drain whatever arrived on both ports.
        for (int i = 0; i < 64; ++i) {
            auto got = sockets_->at.recv_from(std::span<std::uint8_t>(buf), transport::Millis{0});
            if (!got) break;
            core.on_at(std::span<const std::uint8_t>(buf.data(), got->size), got->from, now);
        }
        for (int i = 0; i < 16; ++i) {
            auto got =
                sockets_->navdata.recv_from(std::span<std::uint8_t>(buf), transport::Millis{0});
            if (!got) break;
            core.on_navdata_trigger(got->from, now);
        }
        while (auto f = faults_.try_pop()) {
            struct V {
                DroneCore& core;
                VirtualDrone& vd;
                TimeNs now;
                void operator()(const FaultNavdata& n) { core.set_faults(n.faults); }
                void operator()(const FaultBlackout& b) {
                    core.blackout(now, now + ms_to_ns(b.ms));
                }
                void operator()(const FaultVideoStall& s) { vd.video_stalls_.push(s); }
                void operator()(const FaultVideoReset& r) { vd.video_resets_.push(r); }
                void operator()(const FaultReboot& r) {
                    core.reboot(now, ms_to_ns(r.boot_ms));
                    const auto gen = vd.boot_.latest().value_or(BootState{}).generation;
                    vd.boot_.publish({gen + 1, now + ms_to_ns(r.boot_ms)});
                }
            };
            std::visit(V{core, *this, now}, *f);
        }
        if (video_report_.read_if_newer(report_gen, report)) {
            core.set_video_frame(report.frame_number, report.size);
        }
        out.clear();
        core.advance(now, out);
        for (const auto& d : out) {
            (void)sockets_->navdata.send_to(std::span<const std::uint8_t>(d.bytes), d.to,
                                            transport::Millis{2});
        }
        if (auto dump = core.take_config_dump()) dumps_.push(std::move(*dump));

        camera_.publish({core.pose(), core.video_channel(), now, core.video_codec(),
                         core.video_bitrate_kbps()});
        navdata_seq_.store(core.navdata_sequence());
        core_time_.store(now);
        if (now - last_status > ms_to_ns(20)) {
            last_status = now;
            VirtualDroneStatus st;
            st.flight = core.flight();
            st.drone_state = core.drone_state();
            st.counters = core.counters();
            st.video_frames_sent = report.frames_sent;
            st.video_clients = report.clients;
            st.video_resets = report.resets;
            st.reboot_closes = reboot_closes_.load();
            if (auto b = boot_.latest()) st.booting = now < b->up_at_ns;
            st.render_ms_last = report.render_ms;
            st.encode_ms_last = report.encode_ms;
            st.autopilot_done = core.autopilot_done();
            st.autopilot_active = core.autopilot_active();
            st.collisions = core.collisions();
            st.last_error = report.error;
            status_.publish(std::move(st));
            truth_.publish({now, core.pose(), report.frame_number});
        }
    }
}

void VirtualDrone::video_loop() {
    VideoReport report;
    // The front renderer was built by start(), so a client gets frames as soon as it connects;
    // the bottom camera's, and both at 720p, are built when a client first asks for them.
    std::optional<Renderer>& front = sockets_->front;
    std::optional<Renderer> bottom, front_hd, bottom_hd;
    const Clock& clk = clock();
    const bool stepped = is_stepped(clk);
    // The stream the configuration asks for (video:video_codec, video:bitrate): the encoder is
    // made again when either changes.
    int codec = 0, bitrate_kbps = 0;
    std::unique_ptr<video::H264Encoder> encoder;
    auto configure = [&](int want_codec, int want_kbps) {
        video::H264EncoderConfig ec;
        ec.fps = options_.fps;
        ec.gop = options_.gop;
        ec.width = want_codec == 131 ? 1280 : 640;
        ec.height = want_codec == 131 ? 720 : 360;
        ec.bitrate_bps = want_kbps * 1000;
        auto e = video::H264Encoder::create(ec);
        if (!e) {
            report.error = "encoder: " + to_string(e.error());
            video_report_.publish(report);
            return false;
        }
        encoder = std::move(*e);
        codec = want_codec;
        bitrate_kbps = want_kbps;
        return true;
    };
    if (!configure(129, options_.bitrate_bps / 1000)) return;
    cv::Mat image;
    std::vector<std::uint8_t> au;
    std::vector<std::uint8_t> packet;
    std::uint32_t frame_number = 1;
    std::uint64_t byte_pos = 0;
    const TimeNs period = 1'000'000'000LL / std::max(1, options_.fps);
    const TimeNs t0 = clk.now_ns();
    // A requested reset, waiting for its frame (two bools: g++ 12 misreads an optional here).
    bool reset_pending = false, reset_during_idr = false;
    auto renderer_for = [&](int channel, bool hd) -> Renderer* {
        std::optional<Renderer>& slot =
            channel == 1 ? (hd ? bottom_hd : bottom) : (hd ? front_hd : front);
        if (!slot) {
            const CameraId id = channel == 1 ? CameraId::Bottom : CameraId::Front;
            CameraCalibration cal = camera_calibration(id);
            if (hd) cal = cal.scaled_to(1280, 720);
            auto r = Renderer::create(options_.scene, cal,
                                      channel == 1 ? CameraKind::Bottom : CameraKind::Front);
            if (r) slot.emplace(std::move(*r));
        }
        return slot ? &*slot : (front ? &*front : nullptr);
    };

    std::uint64_t boot_gen = 0;
    BootState boot;
    while (running_) {
        if (boot_.read_if_newer(boot_gen, boot) && !wait_for_boot(sockets_->video, 2, boot)) break;
        if (!sockets_->video.is_open()) {  // could not listen again: report, retry slowly
            report.error = "video port: cannot listen again after the reboot";
            video_report_.publish(report);
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
            continue;
        }
        auto client = sockets_->video.accept(transport::Millis{100});
        if (!client) continue;
        ++report.clients;
        (void)client->set_no_delay(true);
        // Frames are due at whole periods of the drone's clock (k / fps), whenever the client
        // came: a lock-stepped run sees the same frames at the same times on every machine.
        const TimeNs now = clk.now_ns();
        TimeNs next = (now + period - 1) / period * period;
        video_next_due_.store(next);
        video_client_.store(true);
        while (running_) {
            if (!sleep_until(clk, next, running_)) break;
            const TimeNs due = next;  // this frame's time
            next += period;
            if (boot_.read_if_newer(boot_gen, boot)) {
                // Rebooting: the connection dies with the drone's network stack (RST).
                linger l{1, 0};
                ::setsockopt(client->native_handle(), SOL_SOCKET, SO_LINGER, &l, sizeof l);
                client->close();
                ++reboot_closes_;
                if (!wait_for_boot(sockets_->video, 2, boot)) return;
                break;
            }
            if (auto stall = video_stalls_.try_pop()) {
                const TimeNs until = clk.now_ns() + ms_to_ns(stall->ms);
                video_next_due_.store(until + period);  // no frame is due while it stalls
                if (!sleep_until(clk, until, running_)) break;
                next = clk.now_ns() + period;
            }
            auto cam = camera_.latest();
            // Lock-stepped, the picture is of the pose at the frame's time: wait for the physics.
            while (stepped && running_ && (!cam || cam->t_ns < due)) {
                std::this_thread::sleep_for(std::chrono::microseconds(200));
                cam = camera_.latest();
            }
            if (!cam) continue;
            if (cam->codec != codec || cam->bitrate_kbps != bitrate_kbps) {
                if (!configure(cam->codec, cam->bitrate_kbps)) break;
            }
            const bool hd = codec == 131;
            const TimeNs r0 = SteadyClock::instance().now_ns();
            Renderer* renderer = renderer_for(cam->channel, hd);
            if (!renderer) continue;
            renderer->render(cam->pose, image);
            if (image.cols != (hd ? 1280 : 640) || image.rows != (hd ? 720 : 360)) continue;
            const TimeNs r1 = SteadyClock::instance().now_ns();
            bool idr = false;
            auto enc = encoder->encode(image, au, idr);
            const TimeNs r2 = SteadyClock::instance().now_ns();
            report.render_ms = ns_to_ms(r1 - r0);
            report.encode_ms = ns_to_ms(r2 - r1);
            if (!enc) {
                report.error = "encoder: " + to_string(enc.error());
                video_report_.publish(report);
                continue;
            }
            protocol::PaveHeader h;
            h.header_size = 68;
            h.payload_size = static_cast<std::uint32_t>(au.size());
            h.encoded_stream_width = static_cast<std::uint16_t>(image.cols);
            h.encoded_stream_height = static_cast<std::uint16_t>(hd ? 720 : 368);
            h.display_width = static_cast<std::uint16_t>(image.cols);
            h.display_height = static_cast<std::uint16_t>(image.rows);
            h.frame_number = frame_number;
            // The capture time is the pose's: the physics step the image was rendered from.
            h.timestamp = static_cast<std::uint32_t>((std::max(cam->t_ns, t0) - t0) / 1'000'000);
            h.frame_type = idr ? protocol::PaveFrameType::Idr : protocol::PaveFrameType::P;
            h.stream_byte_position_lw = static_cast<std::uint32_t>(byte_pos);
            h.stream_byte_position_uw = static_cast<std::uint32_t>(byte_pos >> 32);
            h.stream_id = static_cast<std::uint16_t>(cam->channel == 1 ? 2 : 1);
            h.advertised_size = h.payload_size;
            h.video_codec = protocol::PaveCodec::H264;
            packet.resize(h.header_size + au.size());
            auto w = protocol::write_pave_header(h, std::span<std::uint8_t>(packet));
            if (!w) continue;
            std::copy(au.begin(), au.end(), packet.begin() + h.header_size);
            byte_pos += au.size();

            if (!reset_pending) {
                if (auto r = video_resets_.try_pop()) {
                    reset_pending = true;
                    reset_during_idr = r->during_idr;
                }
            }
            if (reset_pending && (!reset_during_idr || idr)) {
                reset_pending = false;
                // Half a frame, then a TCP reset (SO_LINGER 0 turns close into RST).
                (void)client->write_all(
                    std::span<const std::uint8_t>(packet.data(), packet.size() / 2),
                    transport::Millis{200});
                linger l{1, 0};
                ::setsockopt(client->native_handle(), SOL_SOCKET, SO_LINGER, &l, sizeof l);
                client->close();
                ++report.resets;
                video_report_.publish(report);
                break;
            }
            auto sent =
                client->write_all(std::span<const std::uint8_t>(packet), transport::Millis{500});
            if (!sent) {
                // A client that went away (closed or reset its end) is a normal end of its
                // connection, not a fault of the drone's; anything else is reported.
                const int why = sent.error().sys_errno;
                if (why != EPIPE && why != ECONNRESET &&
                    sent.error().code != transport::NetErrc::Closed)
                    report.error = "video client: " + sent.error().message();
                video_report_.publish(report);
                break;
            }
            report.frame_number = frame_number++;
            report.size = static_cast<std::uint32_t>(au.size());
            ++report.frames_sent;
            video_report_.publish(report);
            last_frame_number_.store(report.frame_number);
            frames_sent_.store(report.frames_sent);
            video_next_due_.store(next);
        }
        video_client_.store(false);
    }
}

bool VirtualDrone::wait_for_boot(transport::TcpListener& listener, int which,
                                 const BootState& boot) {
    listener.close();  // connecting is refused while the drone boots
    while (running_ && clock().now_ns() < boot.up_at_ns)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    if (!running_) return false;
    auto ep =
        transport::Endpoint::parse(options_.bind_address + ":" + std::to_string(ports_[which]));
    for (int attempt = 0; ep && running_ && attempt < 200; ++attempt) {
        auto l = transport::TcpListener::listen(*ep);
        if (l) {
            listener = std::move(*l);
            return true;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return running_.load();
}

void VirtualDrone::control_loop() {
    transport::TcpStream client;
    std::uint64_t boot_gen = 0;
    BootState boot;
    while (running_) {
        if (boot_.read_if_newer(boot_gen, boot)) {
            if (client.is_open()) {
                linger l{1, 0};
                ::setsockopt(client.native_handle(), SOL_SOCKET, SO_LINGER, &l, sizeof l);
                client.close();
                ++reboot_closes_;
            }
            if (!wait_for_boot(sockets_->control, 3, boot)) return;
        }
        if (!client.is_open()) {
            auto c = sockets_->control.accept(transport::Millis{50});
            if (c) client = std::move(*c);
        }
        auto dump = dumps_.pop_for(std::chrono::milliseconds(20));
        if (!dump || !client.is_open()) continue;
        auto w = client.write_all(*dump, transport::Millis{500});
        if (!w) client.close();
    }
}

}  // namespace gs::sim
