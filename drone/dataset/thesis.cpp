#include "drone/dataset/thesis.hpp"

#include "drone/core/json_text.hpp"
#include "drone/dataset/csv.hpp"
#include "drone/dataset/value_rules.hpp"
#include "drone/dataset/writer.hpp"

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>

namespace gs::dataset {
namespace fs = std::filesystem;

namespace {

bool is_image(const fs::path& p) {
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".bmp";
}

// Natural order: digit runs compare by value ("image_2" < "image_10").
bool natural_less(const std::string& a, const std::string& b) {
    std::size_t i = 0, j = 0;
    while (i < a.size() && j < b.size()) {
        if (std::isdigit(static_cast<unsigned char>(a[i])) &&
            std::isdigit(static_cast<unsigned char>(b[j]))) {
            std::size_t i2 = i, j2 = j;
            while (i2 < a.size() && std::isdigit(static_cast<unsigned char>(a[i2]))) ++i2;
            while (j2 < b.size() && std::isdigit(static_cast<unsigned char>(b[j2]))) ++j2;
            std::string_view da(a.data() + i, i2 - i), db(b.data() + j, j2 - j);
            while (da.size() > 1 && da.front() == '0') da.remove_prefix(1);
            while (db.size() > 1 && db.front() == '0') db.remove_prefix(1);
            if (da.size() != db.size()) return da.size() < db.size();
            if (da != db) return da < db;
            i = i2;
            j = j2;
            continue;
        }
        if (a[i] != b[j]) return a[i] < b[j];
        ++i;
        ++j;
    }
    return a.size() - i < b.size() - j;
}

FileError derr(FileErrorCode c, std::string file, std::string msg, int line = 0, int col = 0) {
    return FileError{c, std::move(file), line, col, std::move(msg)};
}

struct ImuLine {
    double roll, pitch, yaw, vx, vy;
};

Expected<std::vector<ImuLine>, FileError> parse_imu(const std::string& text,
                                                    const std::string& name) {
    std::vector<ImuLine> out;
    int line_no = 0;
    std::size_t pos = 0;
    while (pos < text.size()) {
        std::size_t nl = text.find('\n', pos);
        if (nl == std::string::npos) nl = text.size();
        std::string_view line(text.data() + pos, nl - pos);
        pos = nl + 1;
        ++line_no;
        double v[5];
        int n = 0;
        std::size_t i = 0;
        auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == ','; };
        while (true) {
            while (i < line.size() && blank(line[i])) ++i;
            if (i >= line.size()) break;
            std::size_t e = i;
            while (e < line.size() && !blank(line[e])) ++e;
            const int col = static_cast<int>(i + 1);
            if (n == 5)
                return Unexpected(derr(FileErrorCode::Malformed, name,
                                       "expected 5 values (roll pitch yaw vx vy), got more",
                                       line_no, col));
            std::string_view tok = line.substr(i, e - i);
            if (tok.size() > 1 && tok.front() == '+') tok.remove_prefix(1);
            auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v[n]);
            const std::string shown(line.substr(i, std::min<std::size_t>(e - i, 40)));
            // "nan" is how this layout writes unknown (export_thesis); infinities are malformed.
            if (ec != std::errc() || p != tok.data() + tok.size() || std::isinf(v[n]))
                return Unexpected(derr(FileErrorCode::Malformed, name,
                                       "expected a finite number or nan, got '" + shown + "'",
                                       line_no, col));
            // The value rules of frames.csv (docs/dataset.md 1.1) hold for the same quantities
            // here.
            static constexpr std::string_view kColumns[5] = {"roll_deg", "pitch_deg", "yaw_deg",
                                                             "vx_mps", "vy_mps"};
            if (auto b = value_bounds(kColumns[n]); b && (v[n] < b->lo || v[n] > b->hi))
                return Unexpected(derr(FileErrorCode::OutOfRange, name,
                                       std::string(kColumns[n]) + ": " + shown + " is outside [" +
                                           csv::format_number(b->lo) + ", " +
                                           csv::format_number(b->hi) + "] " + std::string(b->unit),
                                       line_no, col));
            ++n;
            i = e;
        }
        if (n == 0) continue;  // blank line
        if (n != 5)
            return Unexpected(
                derr(FileErrorCode::Malformed, name,
                     "expected 5 values (roll pitch yaw vx vy), got " + std::to_string(n), line_no,
                     static_cast<int>(line.size() + 1)));
        out.push_back({v[0], v[1], v[2], v[3], v[4]});
    }
    return out;
}

// imu_meta.json: flight.json's fps, camera and calibration, each optional.
struct ThesisMeta {
    std::optional<double> fps;
    std::optional<CameraId> camera;
    std::optional<CameraCalibration> calibration;
};

Expected<ThesisMeta, FileError> parse_thesis_meta(const std::string& text,
                                                  const DatasetLimits& limits,
                                                  std::vector<std::string>& warnings) {
    const std::string file = kThesisMetaFile;
    auto parsed = parse_json_text(text, file);
    if (!parsed) return Unexpected(parsed.error());
    const nlohmann::json& j = *parsed;
    if (!j.is_object())
        return Unexpected(derr(FileErrorCode::Malformed, file, "expected a JSON object", 1, 1));
    auto at = [&](FileErrorCode code, const std::string& key, const std::string& msg) {
        auto [l, c] = locate_json_key(text, key);
        return derr(code, file, "'" + key + "': " + msg, l, c);
    };
    ThesisMeta m;
    for (const auto& [key, v] : j.items()) {
        if (key == "fps") {
            if (!v.is_number())
                return Unexpected(at(FileErrorCode::Malformed, key, "expected a number"));
            const double fps = v.get<double>();
            if (!(fps > 0) || fps > limits.max_fps)
                return Unexpected(at(
                    FileErrorCode::OutOfRange, key,
                    v.dump() + " is out of range (0, " + csv::format_number(limits.max_fps) + "]"));
            m.fps = fps;
        } else if (key == "camera") {
            if (v == "front") {
                m.camera = CameraId::Front;
            } else if (v == "bottom") {
                m.camera = CameraId::Bottom;
            } else {
                return Unexpected(
                    at(FileErrorCode::Malformed, key, "expected \"front\" or \"bottom\""));
            }
        } else if (key == "calibration") {
            if (!v.is_object())
                return Unexpected(at(FileErrorCode::Malformed, key, "expected an object"));
            auto c = calibration_from_json(v);
            if (!c) {
                const std::string k = c.error().key.empty() ? key : c.error().key;
                return Unexpected(at(c.error().code, k, "calibration: " + c.error().message));
            }
            m.calibration = *c;
        } else {
            warnings.push_back(file + ": unknown key '" + key + "' ignored");
        }
    }
    return m;
}

// imu_extra.csv: per image, what the IMU line cannot hold (frames.csv's columns).
struct ThesisExtra {
    bool has_time = false;
    std::vector<FrameRow> rows;  // t_ns, vz_mps, altitude_m, gt_* (roll ... vy unused)
};

Expected<ThesisExtra, FileError> parse_thesis_extra(std::string text, std::size_t images) {
    GS_TRY_ASSIGN(auto tr, csv::Table::parse(std::move(text), kThesisExtraFile));
    const csv::Table& t = tr;
    const auto fc = t.column("frame");
    if (!fc)
        return Unexpected(
            derr(FileErrorCode::Missing, kThesisExtraFile, "missing required column 'frame'", 1));
    if (t.rows() != images)
        return Unexpected(derr(FileErrorCode::Inconsistent, kThesisExtraFile,
                               std::to_string(t.rows()) + " rows but the folder holds " +
                                   std::to_string(images) + " images"));
    const auto tc = t.column("t_ms");
    ThesisExtra x;
    x.has_time = tc.has_value();
    x.rows.resize(images);
    for (std::size_t r = 0; r < t.rows(); ++r) {
        FrameRow& row = x.rows[r];
        GS_TRY_ASSIGN(auto fi, t.integer(r, *fc));
        if (fi != static_cast<std::int64_t>(r)) {
            auto e = t.error_at(r, *fc,
                                "expected frame " + std::to_string(r) + ", got " +
                                    std::to_string(fi) + " (rows are images 0, 1, 2 ... in order)");
            e.code = FileErrorCode::Inconsistent;
            return Unexpected(e);
        }
        row.frame = fi;
        if (tc) {
            GS_TRY_ASSIGN(auto tv, t.number(r, *tc));
            if (!std::isfinite(tv))
                return Unexpected(t.error_at(r, *tc, "expected a time, got an empty field"));
            row.nav.t_ns = csv::ms_to_ns_rounded(tv);
            if (r > 0 && row.nav.t_ns < x.rows[r - 1].nav.t_ns) {
                auto e = t.error_at(r, *tc, "time goes backwards");
                e.code = FileErrorCode::Inconsistent;
                return Unexpected(e);
            }
        }
        for (auto [name, dst] : {std::pair{"vz_mps", &row.nav.vz_mps},
                                 {"altitude_m", &row.nav.altitude_m},
                                 {"gt_x_m", &row.gt.x_m},
                                 {"gt_y_m", &row.gt.y_m},
                                 {"gt_z_m", &row.gt.z_m},
                                 {"gt_yaw_deg", &row.gt.yaw_deg}}) {
            const auto col = t.column(name);
            if (!col) continue;
            GS_TRY_ASSIGN(auto v, t.number(r, *col));
            *dst = v;
        }
    }
    return x;
}

std::string thesis_labels_csv(const std::vector<LabelRow>& rows) {
    std::string out = "frame,distance_m,lateral_m\n";
    for (const LabelRow& r : rows)
        out += std::to_string(r.frame) + ',' + csv::format_number(r.distance_m) + ',' +
               csv::format_number(r.lateral_m) + '\n';
    return out;
}

std::string thesis_labels_json(const FlightLabels& l) {
    if (!l.json.empty()) return l.json;
    return "{\n  \"scenario\": \"" + to_string(l.scenario) + "\"\n}\n";
}

// A dataset's labels, those it has, beside the images or frames written into `dst`.
std::optional<FileError> write_labels(const Dataset& d, const fs::path& dst) {
    if (d.labels()) {
        if (auto e = write_file_atomic(dst / "labels.json", thesis_labels_json(*d.labels()),
                                       "labels.json"))
            return e;
    }
    if (d.label_rows())
        return write_file_atomic(dst / "labels.csv", thesis_labels_csv(*d.label_rows()),
                                 "labels.csv");
    return std::nullopt;
}

}  // namespace

Expected<std::size_t, FileError> read_thesis_texts(const std::string& imu_text,
                                                   const std::string& meta_text) {
    if (!meta_text.empty()) {
        std::vector<std::string> warnings;
        auto m = json_boundary(kThesisMetaFile, [&] {
            return parse_thesis_meta(meta_text, DatasetLimits{}, warnings);
        });
        if (!m) return Unexpected(m.error());
    }
    auto imu = parse_imu(imu_text, "imu.txt");
    if (!imu) return Unexpected(imu.error());
    return imu->size();
}

Expected<Dataset, FileError> open_thesis_folder(const fs::path& dir,
                                                const ThesisImportOptions& opts,
                                                const DatasetOpenOptions& open_opts) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        return Unexpected(derr(FileErrorCode::Missing, dir.string(), "not a directory"));
    const DatasetLimits& lim = open_opts.limits;
    if (opts.fps && (!(*opts.fps > 0) || *opts.fps > lim.max_fps))
        return Unexpected(derr(FileErrorCode::OutOfRange, dir.string(),
                               "fps " + csv::format_number(*opts.fps) + " is out of range (0, " +
                                   csv::format_number(lim.max_fps) + "]"));
    std::vector<std::string> images, texts;
    for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator();
         it.increment(ec)) {
        if (!it->is_regular_file(ec)) continue;
        const auto name = it->path().filename().string();
        if (is_image(it->path())) images.push_back(name);
        if (it->path().extension() == ".txt") texts.push_back(name);
    }
    if (ec) return Unexpected(derr(FileErrorCode::Io, dir.string(), ec.message()));
    std::string imu = opts.imu_file;
    if (imu.empty()) {
        if (std::find(texts.begin(), texts.end(), "imu.txt") != texts.end()) {
            imu = "imu.txt";
        } else if (texts.size() == 1) {
            imu = texts.front();
        } else {
            return Unexpected(derr(FileErrorCode::Missing, dir.string(),
                                   texts.empty() ? "no IMU text file (imu.txt)"
                                                 : "no imu.txt and several .txt files"));
        }
    }
    if (fs::path(imu).has_parent_path())
        return Unexpected(derr(FileErrorCode::UnsafePath, imu, "IMU file must be in the folder"));
    GS_TRY_ASSIGN(auto imu_path, resolve_fixed(dir, imu));
    GS_TRY_ASSIGN(auto text, read_text_file(imu_path, imu, lim.max_csv_bytes));
    GS_TRY_ASSIGN(auto lines, parse_imu(text, imu));
    if (images.empty())
        return Unexpected(derr(FileErrorCode::Missing, dir.string(), "no image files"));
    if (lines.size() != images.size())
        return Unexpected(derr(FileErrorCode::Inconsistent, imu,
                               std::to_string(lines.size()) + " lines but the folder holds " +
                                   std::to_string(images.size()) + " images"));
    if (static_cast<std::int64_t>(images.size()) > lim.max_frames)
        return Unexpected(derr(FileErrorCode::OutOfRange, dir.string(), "too many images"));
    std::sort(images.begin(), images.end(), natural_less);
    std::vector<fs::path> paths;
    paths.reserve(images.size());
    for (const auto& name : images) {
        GS_TRY_ASSIGN(auto p, resolve_fixed(dir, name));
        paths.push_back(std::move(p));
    }

    // The side files, when present.
    std::vector<std::string> warnings;
    ThesisMeta meta;
    auto meta_path = resolve_fixed(dir, kThesisMetaFile);
    if (!meta_path) return Unexpected(meta_path.error());
    if (fs::exists(*meta_path, ec)) {
        auto t = read_text_file(*meta_path, kThesisMetaFile, lim.max_json_bytes);
        if (!t) return Unexpected(t.error());
        auto m =
            json_boundary(kThesisMetaFile, [&] { return parse_thesis_meta(*t, lim, warnings); });
        if (!m) return Unexpected(m.error());
        meta = std::move(*m);
    }
    std::optional<ThesisExtra> extra;
    GS_TRY_ASSIGN(auto extra_path, resolve_fixed(dir, kThesisExtraFile));
    if (fs::exists(extra_path, ec)) {
        GS_TRY_ASSIGN(auto t, read_text_file(extra_path, kThesisExtraFile, lim.max_csv_bytes));
        GS_TRY_ASSIGN(auto x, parse_thesis_extra(std::move(t), images.size()));
        extra = std::move(x);
    }
    GS_TRY_ASSIGN(auto labels, read_labels(dir, lim));

    cv::Mat first = cv::imread(paths.front().string(), cv::IMREAD_COLOR);
    if (first.empty())
        return Unexpected(derr(FileErrorCode::Malformed, images.front(), "not a decodable image"));
    DatasetInfo info;
    info.camera = opts.camera.value_or(meta.camera.value_or(CameraId::Front));
    info.width = first.cols;
    info.height = first.rows;
    if (info.width > lim.max_dimension || info.height > lim.max_dimension)
        return Unexpected(derr(FileErrorCode::OutOfRange, images.front(), "image too large"));
    info.fps = opts.fps.value_or(meta.fps.value_or(kThesisDefaultFps));
    info.frames = static_cast<std::int64_t>(images.size());
    info.images = ".";
    info.source = "imported";
    CameraCalibration calib;
    if (meta.calibration) {
        info.calibration = meta.calibration;
        calib = *meta.calibration;
        calib.width = info.width;
        calib.height = info.height;
    } else {
        GS_TRY_ASSIGN(auto cal, default_calibration(info.camera, open_opts.assets_dir));
        calib = cal.scaled_to(info.width, info.height);
    }
    const bool extra_times = extra && extra->has_time;
    if (extra_times && opts.fps)
        warnings.push_back(std::string(kThesisExtraFile) +
                           ": t_ms ignored, the frames are timed by the frame rate given (" +
                           csv::format_number(*opts.fps) + " fps)");
    std::vector<FrameRow> rows;
    rows.reserve(images.size());
    for (std::size_t i = 0; i < images.size(); ++i) {
        FrameRow r;
        if (extra) r = extra->rows[i];
        r.frame = static_cast<std::int64_t>(i);
        if (!extra_times || opts.fps)
            r.nav.t_ns = std::llround(static_cast<double>(i) * 1e9 / info.fps);
        const ImuLine& l = (lines)[i];
        r.nav.roll_deg = l.roll;
        r.nav.pitch_deg = l.pitch;
        r.nav.yaw_deg = l.yaw;
        r.nav.vx_mps = l.vx;
        r.nav.vy_mps = l.vy;
        rows.push_back(r);
    }
    return Dataset::from_parts(dir, info, calib, std::move(rows), std::move(paths),
                               std::move(labels.flight), std::move(labels.rows),
                               std::move(warnings));
}

Expected<Dataset, FileError> import_thesis(const fs::path& src, const fs::path& dst,
                                           const ThesisImportOptions& opts,
                                           const DatasetOpenOptions& open_opts) {
    GS_TRY_ASSIGN(auto d, open_thesis_folder(src, opts, open_opts));
    std::error_code ec;
    if (fs::exists(dst, ec) && (!fs::is_directory(dst, ec) || !fs::is_empty(dst, ec)))
        return Unexpected(
            derr(FileErrorCode::Io, dst.string(), "exists and is not an empty directory"));
    fs::create_directories(dst / "frames", ec);
    if (ec) return Unexpected(derr(FileErrorCode::Io, dst.string(), ec.message()));
    std::string frames = frames_csv_header();
    for (std::size_t i = 0; i < d.frames().size(); ++i) {
        const fs::path& from = d.image_files()[i];
        std::string ext = from.extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(),
                       [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
        char name[32];
        std::snprintf(name, sizeof name, "%06zu", i);
        if (ext == ".bmp") {  // frames/ holds PNG or JPEG only
            cv::Mat img = cv::imread(from.string(), cv::IMREAD_COLOR);
            if (img.empty() ||
                !cv::imwrite((dst / "frames" / (std::string(name) + ".png")).string(), img))
                return Unexpected(
                    derr(FileErrorCode::Io, from.filename().string(), "cannot convert to PNG"));
        } else {
            fs::copy_file(from, dst / "frames" / (name + ext), ec);
            if (ec)
                return Unexpected(derr(FileErrorCode::Io, from.filename().string(), ec.message()));
        }
        frames += frames_csv_row(d.frames()[i]);
    }
    DatasetInfo info = d.info();
    info.images = "frames";
    if (auto e = write_file_atomic(dst / "frames.csv", frames, "frames.csv")) return Unexpected(*e);
    if (auto e = write_labels(d, dst)) return Unexpected(*e);
    if (auto e = write_file_atomic(dst / "flight.json", flight_json_text(info), "flight.json"))
        return Unexpected(*e);
    return Dataset::open(dst, open_opts);
}

std::optional<FileError> export_thesis(const Dataset& d, FrameStore& frames, const fs::path& dst) {
    std::error_code ec;
    if (fs::exists(dst, ec) && (!fs::is_directory(dst, ec) || !fs::is_empty(dst, ec)))
        return derr(FileErrorCode::Io, dst.string(), "exists and is not an empty directory");
    fs::create_directories(dst, ec);
    if (ec) return derr(FileErrorCode::Io, dst.string(), ec.message());
    std::string imu;
    std::string extra = "frame,t_ms,vz_mps,altitude_m,gt_x_m,gt_y_m,gt_z_m,gt_yaw_deg\n";
    cv::Mat img;
    auto num = [](double v) { return std::isnan(v) ? std::string("nan") : csv::format_number(v); };
    for (std::int64_t i = 0; i < d.frame_count(); ++i) {
        if (auto e = frames.read(i, img)) return e;
        char name[32];
        std::snprintf(name, sizeof name, "%06lld.png", static_cast<long long>(i));
        if (!cv::imwrite((dst / name).string(), img))
            return derr(FileErrorCode::Io, name, "cannot write image");
        const FrameRow& row = d.frames()[static_cast<std::size_t>(i)];
        const NavState& s = row.nav;
        imu += num(s.roll_deg) + ' ' + num(s.pitch_deg) + ' ' + num(s.yaw_deg) + ' ' +
               num(s.vx_mps) + ' ' + num(s.vy_mps) + '\n';
        extra += std::to_string(i) + ',' + csv::format_ms(s.t_ns);
        for (double v :
             {s.vz_mps, s.altitude_m, row.gt.x_m, row.gt.y_m, row.gt.z_m, row.gt.yaw_deg})
            extra += ',' + csv::format_number(v);
        extra += '\n';
    }
    nlohmann::ordered_json meta;
    meta["fps"] = d.info().fps;
    meta["camera"] = to_string(d.info().camera);
    if (!d.calibration_is_default())
        meta["calibration"] = calibration_to_json(d.calibration(), false);
    if (auto e = write_file_atomic(dst / kThesisMetaFile, meta.dump(2) + "\n", kThesisMetaFile))
        return e;
    if (auto e = write_file_atomic(dst / kThesisExtraFile, extra, kThesisExtraFile)) return e;
    if (auto e = write_labels(d, dst)) return e;
    return write_file_atomic(dst / "imu.txt", imu, "imu.txt");
}

}  // namespace gs::dataset
