#include "drone/sim/virtual_drone.hpp"

#include "drone/protocol/pave.hpp"
#include "drone/transport/net.hpp"
#include "drone/video/h264_encoder.hpp"

#include <poll.h>
#include <sys/socket.h>

#include <array>
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
TimeNs mono_now() {
    return SteadyClock::instance().now_ns();
}
}  // namespace

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
    co.start = options_.scene.start;
    co.autopilot = options_.scene.autopilot;
    co.autopilot_enabled = options_.autopilot;
    if (!options_.autopilot) co.start.z_m = 0;  // a pilot takes off from the ground
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
        TimeNs now = mono_now();
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
                void operator()(const FaultReboot& r) { core.reboot(now, ms_to_ns(r.boot_ms)); }
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

        camera_.publish({core.pose(), core.video_channel(), now});
        if (now - last_status > ms_to_ns(20)) {
            last_status = now;
            VirtualDroneStatus st;
            st.flight = core.flight();
            st.drone_state = core.drone_state();
            st.counters = core.counters();
            st.video_frames_sent = report.frames_sent;
            st.video_clients = report.clients;
            st.video_resets = report.resets;
            st.render_ms_last = report.render_ms;
            st.encode_ms_last = report.encode_ms;
            st.autopilot_done = core.autopilot_done();
            st.autopilot_active = core.autopilot_active();
            st.last_error = report.error;
            status_.publish(std::move(st));
            truth_.publish({now, core.pose(), report.frame_number});
        }
    }
}

void VirtualDrone::video_loop() {
    VideoReport report;
    // The front renderer was built by start(), so a client gets frames as soon as it connects;
    // the bottom camera's is built only when a client first selects it.
    std::optional<Renderer>& front = sockets_->front;
    std::optional<Renderer> bottom;
    video::H264EncoderConfig ec;
    ec.fps = options_.fps;
    ec.gop = options_.gop;
    ec.bitrate_bps = options_.bitrate_bps;
    auto encoder = video::H264Encoder::create(ec);
    if (!encoder) {
        report.error = "encoder: " + to_string(encoder.error());
        video_report_.publish(report);
        return;
    }
    cv::Mat image(360, 640, CV_8UC3);
    std::vector<std::uint8_t> au;
    std::vector<std::uint8_t> packet;
    std::uint32_t frame_number = 1;
    std::uint64_t byte_pos = 0;
    const TimeNs period = 1'000'000'000LL / std::max(1, options_.fps);
    const TimeNs t0 = mono_now();
    // A requested reset, waiting for its frame (two bools: g++ 12 misreads an optional here).
    bool reset_pending = false, reset_during_idr = false;

    while (running_) {
        auto client = sockets_->video.accept(transport::Millis{100});
        if (!client) continue;
        ++report.clients;
        (void)client->set_no_delay(true);
        TimeNs next = mono_now();
        while (running_) {
            const TimeNs wait = next - mono_now();
            if (wait > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(wait));
            next += period;
            if (auto stall = video_stalls_.try_pop()) {
                std::this_thread::sleep_for(std::chrono::milliseconds(stall->ms));
                next = mono_now() + period;
            }
            auto cam = camera_.latest();
            if (!cam) continue;
            const TimeNs r0 = mono_now();
            Renderer* renderer = &*front;
            if (cam->channel == 1) {
                if (!bottom) {
                    auto b = Renderer::create(options_.scene, camera_calibration(CameraId::Bottom),
                                              CameraKind::Bottom);
                    if (b) bottom.emplace(std::move(*b));
                }
                if (bottom) renderer = &*bottom;
            }
            renderer->render(cam->pose, image);
            const TimeNs r1 = mono_now();
            bool idr = false;
            auto enc = (*encoder)->encode(image, au, idr);
            const TimeNs r2 = mono_now();
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
            h.encoded_stream_width = 640;
            h.encoded_stream_height = 368;
            h.display_width = 640;
            h.display_height = 360;
            h.frame_number = frame_number;
            // The capture time is the pose's: the physics step the image was rendered from.
            h.timestamp = static_cast<std::uint32_t>((std::max(cam->t_ns, t0) - t0) / 1'000'000);
            h.frame_type = idr ? protocol::PaveFrameType::Idr : protocol::PaveFrameType::P;
            h.stream_byte_position_lw = static_cast<std::uint32_t>(byte_pos);
            h.stream_byte_position_uw = static_cast<std::uint32_t>(byte_pos >> 32);
            h.stream_id = static_cast<std::uint16_t>(cam->channel == 1 ? 2 : 1);
            h.advertised_size = h.payload_size;
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
                report.error = "video client: " + sent.error().message();
                video_report_.publish(report);
                break;
            }
            report.frame_number = frame_number++;
            report.size = static_cast<std::uint32_t>(au.size());
            ++report.frames_sent;
            video_report_.publish(report);
        }
    }
}

void VirtualDrone::control_loop() {
    transport::TcpStream client;
    while (running_) {
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
