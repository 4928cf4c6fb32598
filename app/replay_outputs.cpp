#include "app/replay_outputs.hpp"

#include "drone/dataset/thesis.hpp"
#include "drone/dataset/writer.hpp"
#include "vision/plot_image.hpp"

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

namespace gs::app {
namespace fs = std::filesystem;

Expected<dataset::Dataset, std::string> open_any_dataset(const std::string& path,
                                                         std::optional<double> thesis_fps) {
    std::error_code ec;
    if (!fs::is_directory(path, ec)) return Unexpected(path + ": not a directory");
    if (fs::exists(fs::symlink_status(fs::path(path) / "flight.json", ec))) {
        if (thesis_fps)
            return Unexpected(path +
                              ": --fps is only for thesis-style image folders; this is a dataset "
                              "directory, whose frame rate is flight.json's 'fps'");
        auto d = dataset::Dataset::open(path);
        if (!d) return Unexpected(path + ": " + to_string(d.error()));
        return std::move(*d);
    }
    // No flight.json: a thesis-style folder (images + one IMU line per image)?
    dataset::ThesisImportOptions to;
    to.fps = thesis_fps;
    auto t = dataset::open_thesis_folder(path, to);
    if (!t)
        return Unexpected(path +
                          ": no flight.json (not a dataset), and not a thesis-style "
                          "image folder either: " +
                          to_string(t.error()));
    return std::move(*t);
}

std::string fixed(double v, int decimals) {
    if (!std::isfinite(v)) return "-";
    char b[48];
    std::snprintf(b, sizeof b, "%.*f", decimals, v);
    return b;
}

ReplayOutputs::ReplayOutputs(fs::path dir, const CameraCalibration& calib)
    : dir_(std::move(dir)), calib_(calib) {}

ReplayOutputs::~ReplayOutputs() {
    if (decisions_ != nullptr) std::fclose(decisions_);
    if (points_ != nullptr) std::fclose(points_);
}

namespace {
// Creates a CSV file and writes its header line; the error names the file.
std::optional<std::string> open_csv(const fs::path& file, const char* header, std::FILE*& f,
                                    fs::path& path) {
    f = std::fopen(file.c_str(), "w");
    if (f == nullptr) return "cannot create " + file.string();
    path = file;
    if (std::fputs(header, f) < 0) return "cannot write " + file.string();
    return std::nullopt;
}
}  // namespace

std::optional<std::string> ReplayOutputs::open_points(const fs::path& file) {
    return open_csv(file,
                    "frame,t_ms,id,age,region,kind,score,raw_x,raw_y,undist_x,undist_y,"
                    "undist_prev_x,undist_prev_y,stab_x,stab_y,derot_x,derot_y,fb_px,"
                    "structure_xx,structure_xy,structure_yy\n",
                    points_, points_path_);
}

std::optional<std::string> ReplayOutputs::open_decisions(const fs::path& file) {
    return open_csv(file, decisions_csv_header().c_str(), decisions_, decisions_path_);
}

std::optional<std::string> ReplayOutputs::open_video(const fs::path& file,
                                                     const dataset::DatasetInfo& info,
                                                     bool undistort) {
    Mp4WriterConfig c;
    c.width = info.width;
    c.height = info.height;
    c.fps = info.fps;
    auto w = Mp4Writer::create(file, c);
    if (!w) return file.string() + ": " + w.error();
    video_ = std::move(*w);
    undistort_ = undistort;
    if (undistort) undistorter_.set_calibration(calib_);
    return std::nullopt;
}

namespace {

// Overlay primitives (raw, distorted pixels) moved to the undistorted image (same camera matrix).
void undistort_overlay(const vision::Overlay& in, const CameraCalibration& cal,
                       vision::Overlay& out) {
    out = in;  // bars stay where they are: the region bar is drawn across the top
    std::vector<cv::Point2f> pts, und;
    pts.reserve(in.points.size() + 2 * in.lines.size());
    for (const auto& p : in.points) pts.push_back(p.p);
    for (const auto& l : in.lines) {
        pts.push_back(l.a);
        pts.push_back(l.b);
    }
    und.resize(pts.size());
    cal.undistort_points(pts, und);  // undistorted pixels (P = K): the Undistorter's view
    std::size_t k = 0;
    for (auto& p : out.points) p.p = und[k++];
    for (auto& l : out.lines) {
        l.a = und[k++];
        l.b = und[k++];
    }
}

vision::Rgb series_colour(const std::string& name) {
    if (name.find("threshold") != std::string::npos) return {220, 40, 40};
    if (name.find("filtered") != std::string::npos) return {220, 40, 40};
    if (name.find("fitted") != std::string::npos) return {30, 160, 30};
    if (name.find("rejected") != std::string::npos) return {240, 140, 0};
    // The centre's rate channels side by side: each its own colour.
    if (name.find("outline_rate") != std::string::npos) return {0, 150, 150};
    if (name.find("homography_rate") != std::string::npos) return {160, 110, 30};
    if (name.find("rate") != std::string::npos) return {130, 60, 200};
    return {30, 90, 220};
}

// One CSV row built in a fixed buffer (no allocation per row); unknown or non-finite numbers are
// empty cells.
class CsvRow {
public:
    void text(std::string_view v) { put("%.*s", static_cast<int>(v.size()), v.data()); }
    void integer(long long v) { put("%lld", v); }
    void fixed(double v, int decimals) {
        if (std::isfinite(v))
            put("%.*f", decimals, v);
        else
            put("%s", "");
    }
    void general(double v) {
        if (std::isfinite(v))
            put("%.6g", v);
        else
            put("%s", "");
    }
    [[nodiscard]] bool write(std::FILE* f) {
        if (len_ + 1 >= sizeof buf_) return false;  // never: a row is far shorter
        buf_[len_++] = '\n';
        return std::fwrite(buf_, 1, len_, f) == len_;
    }

private:
    template <class... A>
    void put(const char* fmt, A... a) {
        if (len_ > 0 && len_ < sizeof buf_) buf_[len_++] = ',';
        if (len_ >= sizeof buf_) return;
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
#endif
        const int n = std::snprintf(buf_ + len_, sizeof buf_ - len_, fmt, a...);
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif
        if (n > 0) len_ = std::min(sizeof buf_, len_ + static_cast<std::size_t>(n));
    }
    char buf_[512];
    std::size_t len_ = 0;
};
}  // namespace

void ReplayOutputs::write_points(const FrameSample& s, const vision::FrameResult& r) {
    // A frame the classifier rejected (its time not after the previous one's) leaves the result
    // as it was: its points are the previous frame's, not this one's.
    if (r.t_ns != s.t_ns) return;
    const std::string t_ms = dataset::csv::format_ms(s.t_ns);  // as in decisions.csv
    for (const vision::PointRecord& p : r.points) {
        CsvRow row;
        row.integer(s.index);
        row.text(t_ms);
        row.integer(p.id);
        row.integer(p.age);
        row.text(vision::to_string(p.region));
        row.text(p.kind);
        row.general(p.score);
        for (const cv::Point2f& q : {p.raw, p.undist, p.undist_prev, p.stab, p.derot}) {
            row.fixed(static_cast<double>(q.x), 3);
            row.fixed(static_cast<double>(q.y), 3);
        }
        row.fixed(static_cast<double>(p.fb_px), 3);
        for (int k = 0; k < 3; ++k) row.general(static_cast<double>(p.structure[k]));
        if (!row.write(points_)) {
            if (!error_) error_ = "cannot write " + points_path_.string();
            return;
        }
    }
}

void ReplayOutputs::frame(const FrameSample& s, const vision::FrameResult* r) {
    if (decisions_ != nullptr) {
        const std::string row = decisions_csv_row(s.index, s.t_ns, r);
        if (std::fputs(row.c_str(), decisions_) < 0 && !error_)
            error_ = "cannot write " + decisions_path_.string();
    }
    if (r == nullptr) return;
    if (points_ != nullptr) write_points(s, *r);
    if (plots_) collect_series(*r);
    if (video_ && !s.image.empty()) {
        if (undistort_) {
            undistorter_.apply(s.image).copyTo(canvas_);
            undistort_overlay(r->overlay, calib_.scaled_to(s.image.cols, s.image.rows), mapped_);
            vision::draw_overlay(canvas_, mapped_);
        } else {
            s.image.copyTo(canvas_);
            vision::draw_overlay(canvas_, r->overlay);
        }
        if (auto e = video_->write(canvas_); e && !error_) error_ = "overlay.mp4: " + *e;
    }
}

void ReplayOutputs::collect_series(const vision::FrameResult& r) {
    for (const vision::PlotSeries& ps : r.series) {
        if (ps.points.empty()) continue;
        const vision::PlotPoint& p = ps.points.back();
        if (p.x != static_cast<double>(r.frame_index)) continue;  // not updated this frame
        vision::PlotLine& l = series_[ps.name];
        if (l.label.empty()) {
            l.label = ps.name;
            l.colour = series_colour(ps.name);
            l.dashed = ps.name.find("threshold") != std::string::npos;
            l.markers = ps.name.find("rejected") != std::string::npos;
        }
        l.x.push_back(p.x);
        l.y.push_back(p.y);
    }
    for (const vision::TrajectoryTrace& t : r.traces) {
        auto [it, fresh] = traces_.try_emplace(t.id);
        vision::PlotLine& l = it->second;
        if (fresh) {
            // First seen: its earlier x history comes with it.
            for (int i = 0; i + 1 < t.count; ++i) {
                l.x.push_back(static_cast<double>(t.last_frame - (t.count - 1 - i)));
                l.y.push_back(static_cast<double>(t.x[static_cast<std::size_t>(i)]));
            }
        }
        if (t.count > 0) {
            l.x.push_back(static_cast<double>(t.last_frame));
            l.y.push_back(static_cast<double>(t.x[static_cast<std::size_t>(t.count - 1)]));
        }
        const double score = std::isfinite(t.score) ? t.score : 0.0;
        l.colour = vision::blue_to_red(std::clamp(score / 4.0, 0.0, 1.0));
    }
}

std::optional<std::string> ReplayOutputs::write_plots(const fs::path& dir) const {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) return "cannot create " + dir.string() + ": " + ec.message();
    // Every series the classifier published, as numbers: one row per series and frame in which
    // it was updated ("series,frame,value", value empty when unknown), so a plot's figures can be
    // read and compared (the FOE's place, the ego-motion's rejections, the corridor's points).
    std::string csv = "series,frame,value\n";
    char value[64];
    for (const auto& [name, line] : series_)
        for (std::size_t i = 0; i < line.x.size() && i < line.y.size(); ++i) {
            if (std::isfinite(line.y[i]))
                std::snprintf(value, sizeof value, "%.17g", line.y[i]);
            else
                value[0] = '\0';
            csv += name + ',' + std::to_string(std::llround(line.x[i])) + ',' + value + '\n';
        }
    if (auto e = write_file_atomic(dir / "series.csv", csv, "plots/series.csv"))
        return to_string(*e);
    auto save = [&](const std::string& name,
                    const vision::PlotSpec& spec) -> std::optional<std::string> {
        const fs::path f = dir / name;
        if (!cv::imwrite(f.string(), vision::render_plot(spec)))
            return "cannot write " + f.string();
        return std::nullopt;
    };
    auto find = [&](const std::string& n) -> const vision::PlotLine* {
        auto it = series_.find(n);
        return it == series_.end() ? nullptr : &it->second;
    };
    // Each region's score against its threshold.
    for (const auto& [key, title] : std::vector<std::pair<std::string, std::string>>{
             {"left", "left"}, {"centre", "center"}, {"right", "right"}}) {
        vision::PlotSpec s;
        s.title = title + " region: score and threshold";
        s.x_label = "frame";
        for (const char* suffix : {".score", ".threshold"})
            if (const auto* l = find(key + suffix)) s.lines.push_back(*l);
        if (auto e = save(title + "_score.png", s)) return e;
    }
    // The centre's scale series (thesis figs. 3.32-3.36: raw, filtered, fitted).
    vision::PlotSpec c;
    c.title = "center region: homography scale";
    c.x_label = "frame";
    for (const char* name : {"centre.scale_raw", "centre.scale_filtered", "centre.scale_fitted"})
        if (const auto* l = find(name)) c.lines.push_back(*l);
    if (auto e = save("center_scale.png", c)) return e;
    // The expansion rates (flow: the corridor points', the outline's and the homography's)
    // against the threshold.
    vision::PlotSpec rs;
    rs.title = "center region: expansion rate (1/s)";
    rs.x_label = "frame";
    // A channel switched off (no finite sample) stays out, as in the window.
    for (const char* name :
         {"centre.points_rate", "centre.outline_rate", "centre.homography_rate", "centre.rate_raw"})
        if (const auto* l = find(name);
            l && std::any_of(l->y.begin(), l->y.end(), [](double y) { return std::isfinite(y); }))
            rs.lines.push_back(*l);
    if (!rs.lines.empty()) {
        if (const auto* thr = find("centre.threshold")) rs.lines.push_back(*thr);
        if (auto e = save("center_rate.png", rs)) return e;
    }
    // Trajectories' x over frames (thesis fig. 3.25), coloured by their last score.
    vision::PlotSpec t;
    t.title = "trajectories: x over frames (colour: score, blue low, red high)";
    t.x_label = "frame";
    t.y_label = "x (px)";
    t.legend = false;
    t.height = 420;
    for (const auto& [id, l] : traces_)
        if (l.x.size() >= 10) t.lines.push_back(l);
    return save("trajectories_x.png", t);
}

std::optional<std::string> ReplayOutputs::finish(const fs::path& plots_dir) {
    const auto close_csv = [&](std::FILE*& f, const fs::path& path) {
        if (f == nullptr) return;
        if (std::fclose(f) != 0 && !error_) error_ = "cannot write " + path.string();
        f = nullptr;
    };
    close_csv(decisions_, decisions_path_);
    close_csv(points_, points_path_);
    if (video_) {
        if (auto e = video_->close(); e && !error_) error_ = "overlay.mp4: " + *e;
        video_.reset();
    }
    if (plots_ && !plots_dir.empty() && !error_) error_ = write_plots(plots_dir);
    return error_;
}

nlohmann::json summary_json(const dataset::Dataset& d, const ReplaySettings& s,
                            const ReplayStats& st) {
    nlohmann::json j;
    j["dataset"] = d.dir().string();
    j["classifier"] = s.classifier;
    nlohmann::json params = nlohmann::json::object();
    for (const auto& [k, v] : st.params) {
        double x = 0;
        if (!vision::parse_param_value(v, x)) {
            params[k] = v;
        } else if (std::abs(x) < 1e15 && x == std::floor(x)) {
            params[k] = static_cast<std::int64_t>(x);
        } else {
            params[k] = x;
        }
    }
    j["parameters"] = params;
    j["calibration"] = s.calibration_file           ? *s.calibration_file
                       : d.calibration_is_default() ? "default (assets)"
                                                    : "flight.json";
    j["frames"] = st.frames;
    j["processed"] = st.processed;
    j["decode_errors"] = st.decode_errors;
    j["concealed_frames"] = st.concealed;
    j["repaired_frames"] = st.repaired;
    j["rejected_time_steps"] = st.rejected_steps;
    if (!st.first_error.empty()) j["first_decode_error"] = st.first_error;
    j["flagged_frames"] = {
        {"left", st.flagged[0]}, {"center", st.flagged[1]}, {"right", st.flagged[2]}};
    // Frames without a measured decision (decisions.csv writes 0 for them: not unsafe), per
    // region, and why.
    j["unknown_frames"] = {
        {"left", st.unknown[0]}, {"center", st.unknown[1]}, {"right", st.unknown[2]}};
    // Frames judged only for approaching things (the camera still: hovering); what stood ahead
    // was not judged, so they are not "clear" either.
    j["still_frames"] = {{"left", st.still[0]}, {"center", st.still[1]}, {"right", st.still[2]}};
    nlohmann::json reasons = nlohmann::json::object();
    const char* region_names[] = {"left", "center", "right"};
    for (std::size_t r = 0; r < 3; ++r) {
        nlohmann::json by = nlohmann::json::object();
        for (std::size_t k = 0; k < st.unknown_by_reason[r].size(); ++k)
            if (st.unknown_by_reason[r][k] > 0)
                by[vision::to_string(static_cast<vision::UnknownReason>(k))] =
                    st.unknown_by_reason[r][k];
        reasons[region_names[r]] = by;
    }
    j["unknown_reasons"] = reasons;
    j["timing"] = {{"wall_s", st.wall_s},
                   {"cpu_s", st.cpu_s},
                   {"frames_per_s", st.wall_s > 0 ? double(st.processed) / st.wall_s : 0.0},
                   {"read_ms_p50", st.read_ms_p50},
                   {"read_ms_p99", st.read_ms_p99},
                   {"classify_ms_mean", st.classify_ms_mean},
                   {"classify_ms_p50", st.classify_ms_p50},
                   {"classify_ms_p99", st.classify_ms_p99}};
    return j;
}

nlohmann::json score_json(const dataset::FlightScore& s) {
    auto opt = [](const auto& o) { return o ? nlohmann::json(*o) : nlohmann::json(nullptr); };
    return {{"scenario", to_string(s.scenario)},
            {"tp", s.tp},
            {"fp", s.fp},
            {"fn", s.fn},
            {"tn", s.tn},
            {"detection_frame", opt(s.detection_frame)},
            {"detection_distance_m", opt(s.detection_distance_m)},
            {"late_detection_distance_m", opt(s.late_detection_distance_m)},
            {"false_positive_regions", s.false_regions_text()},
            {"first_false_positive_frame", opt(s.first_false_frame)},
            {"flagged_frames",
             {{"left", s.flagged_frames[0]},
              {"center", s.flagged_frames[1]},
              {"right", s.flagged_frames[2]}}},
            {"scored_frames", s.scored_frames},
            {"unscored_frames", s.unscored_frames}};
}

std::optional<std::string> write_json_file(const fs::path& file, const nlohmann::json& j) {
    const std::string text = j.dump(2) + "\n";
    if (auto e = write_file_atomic(file, text, file.filename().string())) return to_string(*e);
    return std::nullopt;
}

}  // namespace gs::app
