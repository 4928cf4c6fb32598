#include "vision/calibration_mode.hpp"

#include "vision/calibration.hpp"
#include "vision/calibration_file.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <mutex>
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

using Clock = std::chrono::steady_clock;

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
    enum class Kind { Start, Stop, Capture, Undo, Reset, Auto, Save };
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

    std::mutex m;
    std::condition_variable cv;
    std::deque<Command> commands;  // guarded by m
    Frame latest;                  // guarded by m
    bool stopping = false;         // guarded by m
    std::atomic<bool> on{false};

    // Worker thread only.
    std::optional<CalibrationSession> cal;
    CalibrationModeState state;
    Frame checked;  // the frame of the latest detection (without its image)
    BoardDetection detection;
    FrameStatus status = FrameStatus::NotFound;
    bool have_check = false;
    std::optional<Clock::time_point> last_detect, last_auto;

    std::thread thread;

    void post(Command c) {
        {
            std::lock_guard lk(m);
            commands.push_back(c);
        }
        cv.notify_one();
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
// least interval_ms ago.
void CalibrationMode::Impl::run() {
    std::unique_lock lk(m);
    while (!stopping) {
        if (!commands.empty()) {
            const Command c = commands.front();
            commands.pop_front();
            lk.unlock();
            handle(c);
            lk.lock();
            continue;
        }
        if (on.load() && !latest.image.empty() && latest.seq != checked.seq) {
            const auto now = Clock::now();
            const auto due =
                last_detect ? *last_detect + std::chrono::milliseconds(opts.interval_ms) : now;
            if (now >= due) {
                const Frame f = latest;
                lk.unlock();
                detect(f, /*allow_auto=*/true);
                lk.lock();
            } else {
                cv.wait_until(lk, due);
            }
            continue;
        }
        cv.wait(lk);
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
        case Kind::Stop: {
            on = false;
            cal.reset();
            clear(state.board);
            std::lock_guard lk(m);
            latest = {};  // let go of the frame buffer
            break;
        }
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
    state.rms_px = res ? res->rms_px : CalibrationModeState::kNaN;
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
    const auto t0 = Clock::now();
    last_detect = t0;
    const ViewResult fr = cal->check(f.image);
    state.detect_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
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
        const auto now = Clock::now();
        if (!last_auto || now - *last_auto >= std::chrono::milliseconds(opts.auto_interval_ms)) {
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
    Frame cur;
    {
        std::lock_guard lk(m);
        cur = latest;
    }
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
    info.source = "ardrone-gs window, calibration mode: " + std::to_string(r->used_views()) +
                  " views of a " + std::to_string(b.cols) + "x" + std::to_string(b.rows) +
                  " board, " + shortest(b.square_m * 1000) + " mm squares";
    const std::filesystem::path path(opts.save_path);
    std::error_code ec;
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path(), ec);
    if (auto saved = cal->save(opts.save_path, info); !saved) {
        state.save_error = saved.error().message();
        return;
    }
    state.saved_path = opts.save_path;
    if (saved_fn) saved_fn(r->camera, info.source, opts.save_path);
}

CalibrationMode::CalibrationMode(CalibrationModeOptions opts, Publish publish, Saved saved)
    : impl_(std::make_unique<Impl>(std::move(opts), std::move(publish), std::move(saved))) {
    impl_->publish();
    impl_->thread = std::thread([this] { impl_->run(); });
}

CalibrationMode::~CalibrationMode() {
    {
        std::lock_guard lk(impl_->m);
        impl_->stopping = true;
    }
    impl_->cv.notify_all();
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
    {
        std::lock_guard lk(impl_->m);
        Impl::Frame& f = impl_->latest;
        f.image = image;  // a header: the caller never rewrites a frame it handed out
        f.index = index;
        f.source_id = source_id;
        ++f.seq;
    }
    impl_->cv.notify_one();
}

bool CalibrationMode::active() const {
    return impl_->on.load();
}

}  // namespace gs::vision
