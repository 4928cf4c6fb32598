#include "drone/dataset/dataset.hpp"

#include "drone/core/json_text.hpp"
#include "drone/dataset/annexb.hpp"
#include "drone/dataset/csv.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace gs::dataset {
namespace fs = std::filesystem;
using nlohmann::json;

std::string to_string(Scenario s) {
    switch (s) {
        case Scenario::Left:
            return "left";
        case Scenario::Right:
            return "right";
        case Scenario::Center:
            return "center";
        case Scenario::None:
            return "none";
    }
    return "none";
}

namespace {

FileError err(FileErrorCode code, std::string file, std::string msg, int line = 0, int col = 0) {
    return FileError{code, std::move(file), line, col, std::move(msg)};
}

class JsonFields {
public:
    JsonFields(const json& obj, const std::string& text, std::string file, std::string prefix = {})
        : obj_(obj), text_(text), file_(std::move(file)), prefix_(std::move(prefix)) {}

    FileError error(FileErrorCode code, const std::string& key, const std::string& msg) const {
        auto [l, c] = locate_json_key(text_, key);
        return err(code, file_, "'" + prefix_ + key + "': " + msg, l, c);
    }
    FileError missing(const std::string& key) const {
        return err(FileErrorCode::Missing, file_, "missing required key '" + prefix_ + key + "'");
    }
    const json* find(const std::string& key) const {
        auto it = obj_.find(key);
        return it == obj_.end() ? nullptr : &*it;
    }
    Expected<std::string, FileError> string(const std::string& key) const {
        const json* v = find(key);
        if (!v) return Unexpected(missing(key));
        if (!v->is_string())
            return Unexpected(error(FileErrorCode::Malformed, key, "expected a string"));
        return v->get<std::string>();
    }
    Expected<std::int64_t, FileError> integer(const std::string& key, std::int64_t lo,
                                              std::int64_t hi) const {
        const json* v = find(key);
        if (!v) return Unexpected(missing(key));
        if (v->is_number_unsigned()) {
            const auto u = v->get<std::uint64_t>();
            if (u > static_cast<std::uint64_t>(hi))
                return Unexpected(range_error(key, std::to_string(u), lo, hi));
            return static_cast<std::int64_t>(u);
        }
        if (!v->is_number_integer())
            return Unexpected(
                error(FileErrorCode::Malformed, key, "expected an integer, got " + v->dump()));
        const auto i = v->get<std::int64_t>();
        if (i < lo || i > hi) return Unexpected(range_error(key, std::to_string(i), lo, hi));
        return i;
    }
    Expected<double, FileError> number(const std::string& key) const {
        const json* v = find(key);
        if (!v) return Unexpected(missing(key));
        if (!v->is_number())
            return Unexpected(
                error(FileErrorCode::Malformed, key, "expected a number, got " + v->dump()));
        const double d = v->get<double>();
        if (!std::isfinite(d))
            return Unexpected(error(FileErrorCode::OutOfRange, key, "not a finite number"));
        return d;
    }

private:
    FileError range_error(const std::string& key, const std::string& got, std::int64_t lo,
                          std::int64_t hi) const {
        return error(
            FileErrorCode::OutOfRange, key,
            got + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
    const json& obj_;
    const std::string& text_;
    std::string file_;
    std::string prefix_;
};

Expected<CameraCalibration, FileError> parse_calibration(const json& obj, const std::string& text,
                                                         const std::string& file,
                                                         const std::string& prefix) {
    JsonFields f(obj, text, file, prefix);
    auto c = calibration_from_json(obj);
    if (c) return *c;
    const CalibrationIssue& i = c.error();
    if (i.code == FileErrorCode::Missing) return Unexpected(f.missing(i.key));
    return Unexpected(f.error(i.code, i.key, i.message));
}

bool has_dotdot_or_root(const fs::path& p) {
    if (p.is_absolute() || p.has_root_name() || p.has_root_directory()) return true;
    for (const auto& part : p)
        if (part == "..") return true;
    return false;
}

bool is_inside(const fs::path& root_canonical, const fs::path& p_canonical) {
    auto r = root_canonical.begin(), re = root_canonical.end();
    auto q = p_canonical.begin(), qe = p_canonical.end();
    for (; r != re; ++r, ++q) {
        if (q == qe || *r != *q) return false;
    }
    return true;
}

// Index encoded in an image name ("000123.png" -> 123), or nullopt.
std::optional<std::int64_t> image_index(const fs::path& name) {
    std::string ext = name.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
    if (ext != ".png" && ext != ".jpg" && ext != ".jpeg") return std::nullopt;
    const std::string stem = name.stem().string();
    if (stem.empty() || stem.size() > 12) return std::nullopt;
    std::int64_t v = 0;
    for (char ch : stem) {
        if (ch < '0' || ch > '9') return std::nullopt;
        v = v * 10 + (ch - '0');
    }
    return v;
}

}  // namespace

Expected<DatasetLabels, FileError> read_labels(const fs::path& dir, const DatasetLimits& lim) {
    DatasetLabels out;
    std::error_code ec;
    GS_TRY_ASSIGN(auto json_path, resolve_fixed(dir, "labels.json"));
    if (fs::exists(json_path, ec)) {
        GS_TRY_ASSIGN(auto text, read_text_file(json_path, "labels.json", lim.max_json_bytes));
        GS_TRY_ASSIGN(auto l, parse_labels_json(text));
        out.flight = std::move(l);
    }
    GS_TRY_ASSIGN(auto csv_path, resolve_fixed(dir, "labels.csv"));
    if (fs::exists(csv_path, ec)) {
        GS_TRY_ASSIGN(auto text, read_text_file(csv_path, "labels.csv", lim.max_csv_bytes));
        GS_TRY_ASSIGN(auto l, parse_labels_csv(std::move(text)));
        out.rows = std::move(l);
    }
    return out;
}

namespace {
Expected<DatasetInfo, FileError> read_flight_json(const std::string& text,
                                                  const DatasetLimits& limits,
                                                  std::vector<std::string>* warnings) {
    const std::string file = "flight.json";
    auto jr = parse_json_text(text, file);
    if (!jr) return Unexpected(jr.error());
    const json& j = *jr;
    if (!j.is_object())
        return Unexpected(err(FileErrorCode::Malformed, file, "expected a JSON object", 1, 1));
    JsonFields f(j, text, file);
    DatasetInfo info;

    GS_TRY_ASSIGN(auto format, f.string("format"));
    if (format != "ardrone-dataset")
        return Unexpected(f.error(FileErrorCode::Malformed, "format",
                                  "expected \"ardrone-dataset\", got \"" + format + "\""));
    GS_TRY_ASSIGN(auto version, f.integer("version", 0, 1'000'000));
    if (version != 1)
        return Unexpected(f.error(FileErrorCode::Unsupported, "version",
                                  "version " + std::to_string(version) +
                                      " is not supported (this reader knows version 1)"));
    info.version = 1;
    GS_TRY_ASSIGN(auto camera, f.string("camera"));
    if (camera == "front") {
        info.camera = CameraId::Front;
    } else if (camera == "bottom") {
        info.camera = CameraId::Bottom;
    } else {
        return Unexpected(f.error(FileErrorCode::Malformed, "camera",
                                  "expected \"front\" or \"bottom\", got \"" + camera + "\""));
    }
    GS_TRY_ASSIGN(auto width, f.integer("width", 1, limits.max_dimension));
    GS_TRY_ASSIGN(auto height, f.integer("height", 1, limits.max_dimension));
    info.width = static_cast<int>(width);
    info.height = static_cast<int>(height);
    GS_TRY_ASSIGN(auto fps, f.number("fps"));
    if (!(fps > 0) || fps > limits.max_fps)
        return Unexpected(f.error(FileErrorCode::OutOfRange, "fps",
                                  csv::format_number(fps) + " is out of range (0, " +
                                      csv::format_number(limits.max_fps) + "]"));
    info.fps = fps;
    if (f.find("frames")) {
        GS_TRY_ASSIGN(auto frames, f.integer("frames", 0, limits.max_frames));
        info.frames = frames;
    }
    for (auto [key, dst] :
         {std::pair<const char*, std::string*>{"video", &info.video}, {"images", &info.images}}) {
        if (!f.find(key)) continue;
        GS_TRY_ASSIGN(auto s, f.string(key));
        if (s.empty()) return Unexpected(f.error(FileErrorCode::Malformed, key, "empty path"));
        if (has_dotdot_or_root(fs::path(s)))
            return Unexpected(
                f.error(FileErrorCode::UnsafePath, key,
                        "must be a relative path inside the dataset, got '" + s + "'"));
        *dst = s;
    }
    if (const json* c = f.find("calibration")) {
        if (!c->is_object())
            return Unexpected(
                f.error(FileErrorCode::Malformed, "calibration", "expected an object"));
        GS_TRY_ASSIGN(auto cal, parse_calibration(*c, text, file, "calibration."));
        cal.width = info.width;
        cal.height = info.height;
        if (cal.source.empty()) cal.source = "flight.json";
        info.calibration = cal;
    }
    if (const json* s = f.find("source")) {
        if (!s->is_string())
            return Unexpected(f.error(FileErrorCode::Malformed, "source", "expected a string"));
        info.source = s->get<std::string>();
    }
    if (const json* r = f.find("realism"); r && !r->is_object())
        return Unexpected(f.error(FileErrorCode::Malformed, "realism", "expected an object"));
    // "realism": what the generator did to a rendered flight (docs/dataset.md); informative.
    static const std::set<std::string> known = {"format", "version",     "camera", "width",
                                                "height", "fps",         "frames", "video",
                                                "images", "calibration", "source", "realism"};
    std::string unknown;
    for (auto it = j.begin(); it != j.end(); ++it) {
        if (known.count(it.key())) continue;
        if (!unknown.empty()) unknown += ", ";
        unknown += it.key();
    }
    if (!unknown.empty() && warnings)
        warnings->push_back("flight.json: unknown keys ignored: " + unknown);
    return info;
}

}  // namespace

Expected<DatasetInfo, FileError> parse_flight_json(const std::string& text,
                                                   const DatasetLimits& limits,
                                                   std::vector<std::string>* warnings) {
    return json_boundary("flight.json", [&] { return read_flight_json(text, limits, warnings); });
}

namespace {

struct NavColumns {
    std::optional<std::size_t> t_ms, roll, pitch, yaw, vx, vy, vz, alt;
};

NavColumns nav_columns(const csv::Table& t) {
    return {t.column("t_ms"),    t.column("roll_deg"),  t.column("pitch_deg"),
            t.column("yaw_deg"), t.column("vx_mps"),    t.column("vy_mps"),
            t.column("vz_mps"),  t.column("altitude_m")};
}

std::optional<FileError> require_columns(const csv::Table& t,
                                         std::initializer_list<const char*> names) {
    for (const char* n : names) {
        if (!t.column(n))
            return err(FileErrorCode::Missing, t.file(),
                       std::string("missing required column '") + n + "'", 1);
    }
    return std::nullopt;
}

// Reads the NavState columns of one row; t_ms must be a number and not go backwards.
std::optional<FileError> read_nav(const csv::Table& t, const NavColumns& c, std::size_t r,
                                  NavState& s, TimeNs prev_t_ns) {
    auto tv = t.number(r, *c.t_ms);
    if (!tv) return tv.error();
    if (!std::isfinite(*tv)) return t.error_at(r, *c.t_ms, "expected a time, got an empty field");
    s.t_ns = csv::ms_to_ns_rounded(*tv);
    if (r > 0 && s.t_ns < prev_t_ns) {
        auto e = t.error_at(r, *c.t_ms,
                            "time goes backwards (" + std::string(t.field(r, *c.t_ms)) + " after " +
                                csv::format_ms(prev_t_ns) + ")");
        e.code = FileErrorCode::Inconsistent;
        return e;
    }
    for (auto [col, dst] : {std::pair{c.roll, &s.roll_deg},
                            {c.pitch, &s.pitch_deg},
                            {c.yaw, &s.yaw_deg},
                            {c.vx, &s.vx_mps},
                            {c.vy, &s.vy_mps},
                            {c.vz, &s.vz_mps},
                            {c.alt, &s.altitude_m}}) {
        if (!col) continue;
        auto v = t.number(r, *col);
        if (!v) return v.error();
        *dst = *v;
    }
    return std::nullopt;
}

}  // namespace

Expected<std::vector<FrameRow>, FileError> parse_frames_csv(std::string text) {
    GS_TRY_ASSIGN(auto tr, csv::Table::parse(std::move(text), "frames.csv"));
    const csv::Table& t = tr;
    if (auto e = require_columns(t, {"frame", "t_ms", "roll_deg"})) return Unexpected(*e);
    const NavColumns nc = nav_columns(t);
    const std::size_t frame_col = *t.column("frame");
    const auto gx = t.column("gt_x_m"), gy = t.column("gt_y_m"), gz = t.column("gt_z_m"),
               gyaw = t.column("gt_yaw_deg");
    std::vector<FrameRow> rows;
    rows.reserve(t.rows());
    TimeNs prev = 0;
    for (std::size_t r = 0; r < t.rows(); ++r) {
        FrameRow row;
        GS_TRY_ASSIGN(auto fi, t.integer(r, frame_col));
        if (fi != static_cast<std::int64_t>(r)) {
            auto e = t.error_at(r, frame_col,
                                "expected frame " + std::to_string(r) + ", got " +
                                    std::to_string(fi) + " (rows are frames 0, 1, 2 ... in order)");
            e.code = FileErrorCode::Inconsistent;
            return Unexpected(e);
        }
        row.frame = fi;
        if (auto e = read_nav(t, nc, r, row.nav, prev)) return Unexpected(*e);
        prev = row.nav.t_ns;
        for (auto [col, dst] : {std::pair{gx, &row.gt.x_m},
                                {gy, &row.gt.y_m},
                                {gz, &row.gt.z_m},
                                {gyaw, &row.gt.yaw_deg}}) {
            if (!col) continue;
            GS_TRY_ASSIGN(auto v, t.number(r, *col));
            *dst = v;
        }
        rows.push_back(row);
    }
    return rows;
}

Expected<std::vector<NavState>, FileError> parse_navdata_csv(std::string text,
                                                             std::vector<std::string>* warnings) {
    auto tr = csv::Table::parse(std::move(text), "navdata.csv", /*tolerate_cut_tail=*/true);
    if (!tr) return Unexpected(tr.error());
    const csv::Table& t = *tr;
    if (warnings && !t.cut_tail_warning().empty()) warnings->push_back(t.cut_tail_warning());
    if (auto e = require_columns(t, {"t_ms"})) return Unexpected(*e);
    const NavColumns nc = nav_columns(t);
    const auto seq = t.column("seq"), state = t.column("state"), ctrl = t.column("ctrl_state"),
               batt = t.column("battery_pct");
    std::vector<NavState> rows;
    rows.reserve(t.rows());
    TimeNs prev = 0;
    // A recording cut short may end inside its last line; when that line is refused it is
    // left out with a warning rather than failing the whole file (docs/dataset.md 1.1).
    auto cut_tail = [&](std::size_t r, const FileError& e) {
        if (r + 1 != t.rows() || !t.last_row_unterminated()) return false;
        if (warnings)
            warnings->push_back(to_string(e) + " (incomplete last line, no newline: ignored)");
        return true;
    };
    for (std::size_t r = 0; r < t.rows(); ++r) {
        NavState s;
        if (auto e = read_nav(t, nc, r, s, prev)) {
            if (cut_tail(r, *e)) break;
            return Unexpected(*e);
        }
        prev = s.t_ns;
        if (seq) {
            auto v = t.u32(r, *seq, false, false);
            if (!v) {
                if (cut_tail(r, v.error())) break;
                return Unexpected(v.error());
            }
            s.seq = *v;
        }
        if (state) {
            auto v = t.u32(r, *state, true, true);
            if (!v) {
                if (cut_tail(r, v.error())) break;
                return Unexpected(v.error());
            }
            s.drone_state = *v;
        }
        if (ctrl) {
            auto v = t.u32(r, *ctrl, true, false);
            if (!v) {
                if (cut_tail(r, v.error())) break;
                return Unexpected(v.error());
            }
            s.ctrl_state = *v;
        }
        if (batt) {
            auto v = t.number(r, *batt);
            if (!v) {
                if (cut_tail(r, v.error())) break;
                return Unexpected(v.error());
            }
            s.battery_pct = *v;
        }
        rows.push_back(s);
    }
    return rows;
}

namespace {
Expected<FlightLabels, FileError> read_labels_json(const std::string& text) {
    const std::string file = "labels.json";
    GS_TRY_ASSIGN(auto jr, parse_json_text(text, file));
    if (!jr.is_object())
        return Unexpected(err(FileErrorCode::Malformed, file, "expected a JSON object", 1, 1));
    JsonFields f(jr, text, file);
    GS_TRY_ASSIGN(auto s, f.string("scenario"));
    FlightLabels l;
    if (s == "left") {
        l.scenario = Scenario::Left;
    } else if (s == "right") {
        l.scenario = Scenario::Right;
    } else if (s == "center") {
        l.scenario = Scenario::Center;
    } else if (s == "none") {
        l.scenario = Scenario::None;
    } else {
        return Unexpected(f.error(FileErrorCode::Malformed, "scenario",
                                  "expected left, right, center or none, got \"" + s + "\""));
    }
    l.json = text;
    return l;
}

}  // namespace

Expected<FlightLabels, FileError> parse_labels_json(const std::string& text) {
    return json_boundary("labels.json", [&] { return read_labels_json(text); });
}

Expected<std::vector<LabelRow>, FileError> parse_labels_csv(std::string text) {
    auto tr = csv::Table::parse(std::move(text), "labels.csv");
    if (!tr) return Unexpected(tr.error());
    const csv::Table& t = *tr;
    if (auto e = require_columns(t, {"frame", "distance_m"})) return Unexpected(*e);
    const auto fc = *t.column("frame"), dc = *t.column("distance_m");
    const auto lc = t.column("lateral_m");
    std::vector<LabelRow> rows;
    rows.reserve(t.rows());
    for (std::size_t r = 0; r < t.rows(); ++r) {
        LabelRow row;
        GS_TRY_ASSIGN(auto fi, t.integer(r, fc));
        if (fi < 0) return Unexpected(t.error_at(r, fc, "negative frame index"));
        row.frame = fi;
        GS_TRY_ASSIGN(auto d, t.number(r, dc));
        row.distance_m = d;
        if (lc) {
            GS_TRY_ASSIGN(auto l, t.number(r, *lc));
            row.lateral_m = l;
        }
        rows.push_back(row);
    }
    return rows;
}

namespace {

// Where `dir / relative` really is when it exists and (through symlinks) leaves `dir`; nullopt
// when it is absent or inside.
Expected<std::optional<fs::path>, FileError> escape_target(const fs::path& dir,
                                                           const fs::path& relative) {
    const fs::path p = dir / relative;
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(p, ec)))
        return std::optional<fs::path>();  // absent: nothing to escape through
    const fs::path root = fs::weakly_canonical(dir.empty() ? fs::path(".") : dir, ec);
    if (ec) return Unexpected(err(FileErrorCode::Io, dir.string(), ec.message()));
    const fs::path real = fs::weakly_canonical(p, ec);
    if (ec) return Unexpected(err(FileErrorCode::Io, relative.generic_string(), ec.message()));
    if (is_inside(root, real)) return std::optional<fs::path>();
    return std::optional<fs::path>(real);
}

}  // namespace

Expected<fs::path, FileError> resolve_inside(const fs::path& dir, const std::string& relative,
                                             const std::string& what) {
    const fs::path rel(relative);
    if (relative.empty() || has_dotdot_or_root(rel))
        return Unexpected(err(
            FileErrorCode::UnsafePath, "flight.json",
            "'" + what + "' must be a relative path inside the dataset, got '" + relative + "'"));
    GS_TRY_ASSIGN(auto out, escape_target(dir, rel));
    if (out)
        return Unexpected(
            err(FileErrorCode::UnsafePath, "flight.json",
                "'" + what + "' (" + relative + ") resolves outside the dataset directory"));
    return dir / rel;
}

Expected<fs::path, FileError> resolve_fixed(const fs::path& dir, const std::string& name) {
    GS_TRY_ASSIGN(auto out, escape_target(dir, fs::path(name)));
    if (out)
        return Unexpected(err(FileErrorCode::UnsafePath, name,
                              "resolves outside the dataset directory (to " + (out)->string() +
                                  "); only files inside it are read"));
    return dir / name;
}

std::optional<fs::path> Dataset::raw_dir() const {
    return has_raw_ ? std::optional<fs::path>(dir_ / "raw") : std::nullopt;
}

Dataset Dataset::from_parts(fs::path dir, DatasetInfo info, CameraCalibration calib,
                            std::vector<FrameRow> frames, std::vector<fs::path> images,
                            std::optional<FlightLabels> labels,
                            std::optional<std::vector<LabelRow>> label_rows,
                            std::vector<std::string> warnings) {
    Dataset d;
    d.dir_ = std::move(dir);
    d.calibration_is_default_ = !info.calibration;
    d.info_ = std::move(info);
    d.calibration_ = std::move(calib);
    d.frames_ = std::move(frames);
    d.image_files_ = std::move(images);
    d.labels_ = std::move(labels);
    d.label_rows_ = std::move(label_rows);
    d.warnings_ = std::move(warnings);
    return d;
}

Expected<Dataset, FileError> Dataset::open(const fs::path& dir, const DatasetOpenOptions& opts) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        return Unexpected(err(FileErrorCode::Missing, dir.string(), "not a directory"));
    Dataset d;
    d.dir_ = dir;
    const DatasetLimits& lim = opts.limits;

    // Every file with a fixed name is resolved first: none may lead out of the dataset.
    GS_TRY_ASSIGN(auto flight_path, resolve_fixed(dir, "flight.json"));
    GS_TRY_ASSIGN(auto flight_text, read_text_file(flight_path, "flight.json", lim.max_json_bytes));
    GS_TRY_ASSIGN(auto info, parse_flight_json(flight_text, lim, &d.warnings_));
    d.info_ = std::move(info);

    GS_TRY_ASSIGN(auto frames_path, resolve_fixed(dir, "frames.csv"));
    GS_TRY_ASSIGN(auto frames_text, read_text_file(frames_path, "frames.csv", lim.max_csv_bytes));
    GS_TRY_ASSIGN(auto frames, parse_frames_csv(std::move(frames_text)));
    d.frames_ = std::move(frames);
    const auto rows = static_cast<std::int64_t>(d.frames_.size());
    if (rows > lim.max_frames)
        return Unexpected(
            err(FileErrorCode::OutOfRange, "frames.csv",
                std::to_string(rows) + " rows (limit " + std::to_string(lim.max_frames) + ")"));
    if (d.info_.frames && *d.info_.frames != rows) {
        auto [l, c] = locate_json_key(flight_text, "frames");
        return Unexpected(err(FileErrorCode::Inconsistent, "flight.json",
                              "'frames' is " + std::to_string(*d.info_.frames) +
                                  " but frames.csv has " + std::to_string(rows) + " rows",
                              l, c));
    }

    // Pixels: video.h264 (source of truth) and/or frames/.
    GS_TRY_ASSIGN(auto video, resolve_inside(dir, d.info_.video, "video"));
    GS_TRY_ASSIGN(auto images, resolve_inside(dir, d.info_.images, "images"));
    const std::string video_name = d.info_.video;
    const std::string images_name = d.info_.images + "/";
    if (fs::exists(video, ec)) {
        if (!fs::is_regular_file(video, ec))
            return Unexpected(err(FileErrorCode::Malformed, video_name, "not a regular file"));
        GS_TRY_ASSIGN(auto index, index_annexb_file(video, video_name));
        const auto units = static_cast<std::int64_t>(index.size());
        if (units < rows)
            return Unexpected(err(FileErrorCode::Inconsistent, video_name,
                                  "holds " + std::to_string(units) +
                                      " access units but frames.csv has " + std::to_string(rows) +
                                      " rows (truncated?)"));
        if (units > rows)
            d.warnings_.push_back(video_name + ": " + std::to_string(units - rows) +
                                  " access units after the last frames.csv row are ignored");
        index.resize(static_cast<std::size_t>(rows));
        d.video_path_ = video;
        d.video_units_ = std::move(index);
    }
    if (fs::is_directory(images, ec)) {
        std::map<std::int64_t, fs::path> found;
        std::int64_t extra = 0;
        std::optional<FileError> problem;
        for (auto it = fs::directory_iterator(images, ec); !ec && it != fs::directory_iterator();
             it.increment(ec)) {
            const auto idx = image_index(it->path().filename());
            if (!idx) continue;
            if (*idx >= rows) {
                ++extra;
                continue;
            }
            if (it->is_symlink(ec)) {
                GS_TRY(resolve_fixed(dir, fs::relative(it->path(), dir, ec).generic_string()));
            }
            if (!found.emplace(*idx, it->path()).second && !problem) {
                problem = err(FileErrorCode::Inconsistent, images_name,
                              "two images for frame " + std::to_string(*idx) + " (" +
                                  found[*idx].filename().string() + " and " +
                                  it->path().filename().string() + ")");
            }
        }
        if (ec) return Unexpected(err(FileErrorCode::Io, images_name, ec.message()));
        if (!problem && static_cast<std::int64_t>(found.size()) != rows) {
            std::int64_t first_missing = 0;
            while (found.count(first_missing)) ++first_missing;
            char name[32];
            std::snprintf(name, sizeof name, "%06lld", static_cast<long long>(first_missing));
            problem =
                err(FileErrorCode::Inconsistent, images_name,
                    "holds " + std::to_string(found.size()) + " of the " + std::to_string(rows) +
                        " frames in frames.csv; frame " + std::to_string(first_missing) + " (" +
                        name + ".png or .jpg) is missing");
        }
        if (problem) {
            if (!d.video_path_) return Unexpected(*problem);
            d.warnings_.push_back(to_string(*problem) + " (ignored: " + video_name +
                                  " is present)");
        } else {
            d.image_files_.reserve(found.size());
            for (auto& [i, p] : found) d.image_files_.push_back(std::move(p));
            if (extra > 0)
                d.warnings_.push_back(images_name + ": " + std::to_string(extra) +
                                      " images after the last frames.csv row are ignored");
        }
    }
    if (!d.video_path_ && d.image_files_.empty() && rows > 0)
        return Unexpected(err(
            FileErrorCode::Missing, "flight.json",
            "neither '" + video_name + "' nor '" + images_name + "' is present in the dataset"));

    // Calibration: flight.json, else the shipped default of that camera.
    if (d.info_.calibration) {
        d.calibration_ = *d.info_.calibration;
    } else {
        auto def = default_calibration(d.info_.camera, opts.assets_dir);
        if (!def) {
            auto e = def.error();
            e.message = "no calibration in flight.json and the default failed: " + e.message;
            return Unexpected(e);
        }
        if (def->width > 0 && (def->width != d.info_.width || def->height != d.info_.height))
            d.warnings_.push_back("default " + to_string(d.info_.camera) + " calibration (" +
                                  std::to_string(def->width) + "x" + std::to_string(def->height) +
                                  ") scaled to " + std::to_string(d.info_.width) + "x" +
                                  std::to_string(d.info_.height));
        d.calibration_ = def->scaled_to(d.info_.width, d.info_.height);
        d.calibration_is_default_ = true;
    }

    auto navdata_path = resolve_fixed(dir, "navdata.csv");
    if (!navdata_path) return Unexpected(navdata_path.error());
    if (fs::exists(*navdata_path, ec)) {
        auto text = read_text_file(*navdata_path, "navdata.csv", lim.max_csv_bytes);
        if (!text) return Unexpected(text.error());
        auto nav = parse_navdata_csv(std::move(*text), &d.warnings_);
        if (!nav) return Unexpected(nav.error());
        d.navdata_ = std::move(*nav);
        d.has_navdata_ = true;
    }
    GS_TRY_ASSIGN(auto labels, read_labels(dir, lim));
    d.labels_ = std::move(labels.flight);
    d.label_rows_ = std::move(labels.rows);
    GS_TRY_ASSIGN(auto raw_path, resolve_fixed(dir, "raw"));
    d.has_raw_ = fs::is_directory(raw_path, ec);
    return d;
}

}  // namespace gs::dataset
