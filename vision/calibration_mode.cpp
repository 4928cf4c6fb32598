#include "vision/calibration_mode.hpp"
#include "drone/core/unknown.hpp"

#include "drone/core/clock.hpp"
#include "drone/core/sync.hpp"
#include "vision/calibration.hpp"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <thread>

namespace gs::vision {

bool CalibrationBoard::valid() const {
    return BoardSpec{cols, rows, square_m}.valid();
}

const char* to_string(ViewCheck c) {
    switch (c) {
        case ViewCheck::None:
            return "nothing checked yet";
        case ViewCheck::AddsCoverage:
            return "board found, adds coverage";
        case ViewCheck::NoNewCoverage:
            return "adds no coverage";
        case ViewCheck::NotFound:
            return "board not found";
        case ViewCheck::Blurry:
            return "board blurry";
        case ViewCheck::SizeMismatch:
            return "image size differs from the kept views";
        case ViewCheck::EmptyImage:
            return "empty image";
    }
    return "?";
}

namespace {

std::string shortest(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
}

}  // namespace

struct CalibrationMode::Impl {
    struct Frame {
        cv::Mat image;
        std::int64_t index = -1;
        std::uint64_t source_id = 0;
        std::uint64_t seq = 0;
    };
    // NewFrame only wakes the worker: the frame itself is in `latest`.
    enum class Kind { Start, Stop, Capture, Undo, Reset, Auto, Save, NewFrame };
    struct Command {
        Kind kind = Kind::Capture;
        CalibrationBoard board;
        bool on = false;
    };

    Impl(CalibrationModeOptions o, Publish p, Saved s)
        : opts(std::move(o)), publish_fn(std::move(p)), saved_fn(std::move(s)) {
        state.save_path = opts.save_path;
    }

    const CalibrationModeOptions opts;
    const Publish publish_fn;
    const Saved saved_fn;

    // Shared with the callers' threads: commands in order, the newest frame, the on flag.
    static constexpr std::size_t kCommandQueue = 64;
    BoundedQueue<Command> commands{kCommandQueue};
    LatestValue<Frame> latest;
    std::atomic<std::uint64_t> offered{0};  // frames offered (Frame::seq)
    std::atomic<bool> wake_pending{false};  // a NewFrame is queued
    std::atomic<bool> on{false};
    const Clock& clock = SteadyClock::instance();

    // Worker thread only.
    std::optional<CalibrationSession> cal;
    CalibrationModeState state;
    Frame checked;  // the frame of the latest detection (without its image)
    BoardDetection detection;
    FrameStatus status = FrameStatus::NotFound;
    bool have_check = false;
    std::optional<TimeNs> last_detect, last_auto;

    std::thread thread;

    // A command refused by a full queue (a caller far ahead of the worker) is dropped and
    // counted by the queue; the state the worker publishes shows what was done.
    void post(Command c) { (void)commands.push(std::move(c)); }
    void wake() {
        if (!wake_pending.exchange(true) && !commands.push(Command{Kind::NewFrame, {}, false}))
            wake_pending = false;
    }
    void run();
    void handle(const Command& c);
    void detect(const Frame& f, bool allow_auto);
    void capture(bool automatic);
    void save();
    void refresh();
    void publish() {
        if (publish_fn) publish_fn(state);
    }
    void clear(const CalibrationBoard& board) {
        const bool was_auto = state.auto_capture;
        state = CalibrationModeState{};
        state.save_path = opts.save_path;
        state.board = board;
        state.auto_capture = was_auto;
        checked = {};
        detection = {};
        status = FrameStatus::NotFound;
        have_check = false;
    }
};

// Commands first; then the newest frame when it is unchecked and the last detection started at
// least interval_ms ago. Closing the queue stops the worker (queued commands are dropped).
void CalibrationMode::Impl::run() {
    // Waits are bounded so that a wake-up the full queue refused costs at most this much.
    constexpr TimeNs kMaxWaitNs = 200 * kNsPerMs;
    for (;;) {
        if (commands.closed()) return;
        if (auto c = commands.try_pop()) {
            if (c->kind == Kind::NewFrame)
                wake_pending = false;
            else
                handle(*c);
            continue;
        }
        TimeNs wait_ns = kMaxWaitNs;
        if (on.load()) {
            const std::optional<Frame> f = latest.latest();
            if (f && !f->image.empty() && f->seq != checked.seq) {
                const TimeNs now = clock.now_ns();
                const TimeNs due = last_detect ? *last_detect + ms_to_ns(opts.interval_ms) : now;
                if (now >= due) {
                    detect(*f, /*allow_auto=*/true);
                    continue;
                }
                wait_ns = std::min(wait_ns, due - now);
            }
        }
        if (auto c = commands.pop_for(std::chrono::nanoseconds(wait_ns))) {
            if (c->kind == Kind::NewFrame)
                wake_pending = false;
            else if (!commands.closed())
                handle(*c);
        }
    }
}

void CalibrationMode::Impl::handle(const Command& c) {
    switch (c.kind) {
        case Kind::Start:
            clear(c.board);
            if (!c.board.valid()) {
                cal.reset();
                on = false;
                state.result_error = "board " + std::to_string(c.board.cols) + "x" +
                                     std::to_string(c.board.rows) + ", " +
                                     shortest(c.board.square_m) +
                                     " m squares: needs 3..100 inner corners per side and a "
                                     "square size above 0";
            } else {
                cal.emplace(BoardSpec{c.board.cols, c.board.rows, c.board.square_m},
                            SessionOptions{});
                state.min_views = CalibrationOptions{}.min_views;
                state.active = true;
                on = true;
            }
            break;
        case Kind::Stop:
            on = false;
            cal.reset();
            clear(state.board);
            latest.publish(Frame{});  // let go of the frame buffer
            break;
        case Kind::Capture:
            capture(false);
            break;
        case Kind::Undo:
            if (cal) {
                cal->remove_last_view();
                refresh();
            }
            break;
        case Kind::Reset:
            if (cal) {
                cal->reset();
                refresh();
            }
            break;
        case Kind::Auto:
            state.auto_capture = c.on;
            break;
        case Kind::Save:
            save();
            break;
        case Kind::NewFrame:
            return;  // handled by run()
    }
    publish();
}

// Views, coverage and the running calibration from the CalibrationSession, and the latest
// check's coverage gain against the views kept now.
void CalibrationMode::Impl::refresh() {
    if (!cal) return;
    state.views = static_cast<int>(cal->view_count());
    const CoverageMap& g = cal->coverage();
    state.coverage_size = g.image_size();
    state.grid_cols = g.grid_cols();
    state.grid_rows = g.grid_rows();
    state.coverage.clear();
    for (int r = 0; r < g.grid_rows(); ++r)
        for (int col = 0; col < g.grid_cols(); ++col) state.coverage.push_back(g.count(col, r));
    state.coverage_fraction = g.grid_cols() > 0 ? g.fraction() : 0.0;
    state.corner_regions = g.grid_cols() > 0 ? g.corner_regions_covered() : 0;
    const auto& res = cal->result();
    state.has_result = res.has_value();
    state.camera = res ? res->camera : CameraCalibration{};
    state.rms_px = res ? res->rms_px : kUnknown;
    state.used_views = res ? res->used_views() : 0;
    state.result_error = cal->last_error() ? cal->last_error()->message() : std::string{};

    if (have_check && status == FrameStatus::Accepted) {
        state.new_cells = g.views() > 0
                              ? g.new_cells(detection.corners)
                              : CoverageMap(state.image_size).new_cells(detection.corners);
        state.check = cal->view_count() > 0 && state.new_cells == 0 ? ViewCheck::NoNewCoverage
                                                                    : ViewCheck::AddsCoverage;
    }
}

void CalibrationMode::Impl::detect(const Frame& f, bool allow_auto) {
    if (!cal) return;
    const TimeNs t0 = clock.now_ns();
    last_detect = t0;
    const ViewResult fr = cal->check(f.image);
    state.detect_ms = ns_to_ms(clock.now_ns() - t0);
    checked = f;
    checked.image = cv::Mat();  // the detection is all that is kept of it
    detection = fr.detection;
    status = fr.status;
    have_check = true;
    ++state.detections;
    state.frame = f.index;
    state.source_id = f.source_id;
    state.image_size = f.image.size();
    state.corners = fr.detection.corners;
    state.new_cells = fr.new_cells;
    switch (fr.status) {
        case FrameStatus::Accepted:
        case FrameStatus::NoNewCoverage:
            state.check = cal->view_count() > 0 && fr.new_cells == 0 ? ViewCheck::NoNewCoverage
                                                                     : ViewCheck::AddsCoverage;
            break;
        case FrameStatus::NotFound:
            state.check = ViewCheck::NotFound;
            break;
        case FrameStatus::Blurry:
            state.check = ViewCheck::Blurry;
            break;
        case FrameStatus::SizeMismatch:
            state.check = ViewCheck::SizeMismatch;
            break;
        case FrameStatus::EmptyImage:
            state.check = ViewCheck::EmptyImage;
            break;
    }
    if (allow_auto && state.auto_capture && state.check == ViewCheck::AddsCoverage) {
        const TimeNs now = clock.now_ns();
        if (!last_auto || now - *last_auto >= ms_to_ns(opts.auto_interval_ms)) {
            last_auto = now;
            capture(true);
        }
    }
    publish();
}

// Keeps the newest frame if CalibrationSession accepts it. A frame already checked keeps its
// detection (no second detection); a newer one is checked first.
void CalibrationMode::Impl::capture(bool automatic) {
    ++state.captures;
    state.last_capture_kept = false;
    if (!cal) {
        state.last_capture = "not kept: the calibration mode is off";
        return;
    }
    const Frame cur = latest.latest().value_or(Frame{});
    if (!cur.image.empty() && cur.seq != checked.seq) detect(cur, /*allow_auto=*/false);
    if (!have_check) {
        state.last_capture = "not kept: no video frame yet";
        return;
    }
    ViewResult fr;
    if (status == FrameStatus::SizeMismatch) {
        fr.status = FrameStatus::SizeMismatch;
    } else {
        fr = cal->add_detection(detection, /*require_new_coverage=*/true);
    }
    state.last_capture_kept = fr.accepted();
    char buf[160];
    if (fr.accepted())
        std::snprintf(buf, sizeof buf, "%sview %zu kept (frame %lld, +%d cells)",
                      automatic ? "auto capture: " : "", cal->view_count(),
                      static_cast<long long>(checked.index), fr.new_cells);
    else
        std::snprintf(buf, sizeof buf, "frame %lld not kept: %s",
                      static_cast<long long>(checked.index), to_string(fr.status));
    state.last_capture = buf;
    refresh();
}

void CalibrationMode::Impl::save() {
    ++state.saves;
    state.save_error.clear();
    if (!cal) {
        state.save_error = "the calibration mode is off";
        return;
    }
    if (opts.save_path.empty()) {
        state.save_error = "no calibration file configured";
        return;
    }
    auto r = cal->calibrate();
    refresh();
    if (!r) {
        state.save_error = r.error().message() + "; nothing saved";
        return;
    }
    const BoardSpec& b = cal->board();
    CalibrationInfo info;
    info.camera = opts.camera;
    const std::string source =
        "ardrone-gs window, calibration mode: " + std::to_string(r->used_views()) + " views of a " +
        std::to_string(b.cols) + "x" + std::to_string(b.rows) + " board, " +
        shortest(b.square_m * 1000) + " mm squares";
    const std::filesystem::path path(opts.save_path);
    std::error_code ec;
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), ec);
    if (auto saved = cal->save(opts.save_path, info, source); !saved) {
        state.save_error = saved.error().message();
        return;
    }
    state.saved_path = opts.save_path;
    if (saved_fn) saved_fn(r->camera, source, opts.save_path);
}

CalibrationMode::CalibrationMode(CalibrationModeOptions opts, Publish publish, Saved saved)
    : impl_(std::make_unique<Impl>(std::move(opts), std::move(publish), std::move(saved))) {
    impl_->publish();
    impl_->thread = std::thread([this] { impl_->run(); });
}

CalibrationMode::~CalibrationMode() {
    impl_->commands.close();
    if (impl_->thread.joinable()) impl_->thread.join();
}

void CalibrationMode::start(const CalibrationBoard& board) {
    impl_->post({Impl::Kind::Start, board, false});
}
void CalibrationMode::stop() {
    impl_->post({Impl::Kind::Stop, {}, false});
}
void CalibrationMode::capture() {
    impl_->post({Impl::Kind::Capture, {}, false});
}
void CalibrationMode::undo() {
    impl_->post({Impl::Kind::Undo, {}, false});
}
void CalibrationMode::reset() {
    impl_->post({Impl::Kind::Reset, {}, false});
}
void CalibrationMode::set_auto_capture(bool on) {
    impl_->post({Impl::Kind::Auto, {}, on});
}
void CalibrationMode::save() {
    impl_->post({Impl::Kind::Save, {}, false});
}

void CalibrationMode::offer(const cv::Mat& image, std::int64_t index, std::uint64_t source_id,
                            bool even_inactive) {
    if ((!impl_->on.load() && !even_inactive) || image.empty()) return;
    // The image is a header: the caller never rewrites a frame it handed out.
    impl_->latest.publish(Impl::Frame{image, index, source_id, ++impl_->offered});
    impl_->wake();
}

bool CalibrationMode::active() const {
    return impl_->on.load();
}

}  // namespace gs::vision
