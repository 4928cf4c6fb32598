#include "drone/dataset/thesis.hpp"

#include "drone/dataset/csv.hpp"
#include "drone/dataset/writer.hpp"

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>

namespace gs {
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

DatasetError derr(DatasetErrorCode c, std::string file, std::string msg, int line = 0,
                  int col = 0) {
    return DatasetError{c, std::move(file), line, col, std::move(msg)};
}

struct ImuLine {
    double roll, pitch, yaw, vx, vy;
};

Expected<std::vector<ImuLine>, DatasetError> parse_imu(const std::string& text,
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
                return Unexpected(derr(DatasetErrorCode::Malformed, name,
                                       "expected 5 values (roll pitch yaw vx vy), got more",
                                       line_no, col));
            std::string_view tok = line.substr(i, e - i);
            if (tok.size() > 1 && tok.front() == '+') tok.remove_prefix(1);
            auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v[n]);
            if (ec != std::errc() || p != tok.data() + tok.size())
                return Unexpected(
                    derr(DatasetErrorCode::Malformed, name,
                         "expected a number, got '" +
                             std::string(line.substr(i, std::min<std::size_t>(e - i, 40))) + "'",
                         line_no, col));
            ++n;
            i = e;
        }
        if (n == 0) continue;  // blank line
        if (n != 5)
            return Unexpected(
                derr(DatasetErrorCode::Malformed, name,
                     "expected 5 values (roll pitch yaw vx vy), got " + std::to_string(n), line_no,
                     static_cast<int>(line.size() + 1)));
        out.push_back({v[0], v[1], v[2], v[3], v[4]});
    }
    return out;
}

}  // namespace

Expected<Dataset, DatasetError> open_thesis_folder(const fs::path& dir,
                                                   const ThesisImportOptions& opts,
                                                   const DatasetOpenOptions& open_opts) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        return Unexpected(derr(DatasetErrorCode::Missing, dir.string(), "not a directory"));
    if (!(opts.fps > 0) || opts.fps > open_opts.limits.max_fps)
        return Unexpected(derr(DatasetErrorCode::OutOfRange, dir.string(), "fps out of range"));
    std::vector<std::string> images, texts;
    for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator();
         it.increment(ec)) {
        if (!it->is_regular_file(ec)) continue;
        const auto name = it->path().filename().string();
        if (is_image(it->path())) images.push_back(name);
        if (it->path().extension() == ".txt") texts.push_back(name);
    }
    if (ec) return Unexpected(derr(DatasetErrorCode::Io, dir.string(), ec.message()));
    std::string imu = opts.imu_file;
    if (imu.empty()) {
        if (std::find(texts.begin(), texts.end(), "imu.txt") != texts.end()) {
            imu = "imu.txt";
        } else if (texts.size() == 1) {
            imu = texts.front();
        } else {
            return Unexpected(derr(DatasetErrorCode::Missing, dir.string(),
                                   texts.empty() ? "no IMU text file (imu.txt)"
                                                 : "no imu.txt and several .txt files"));
        }
    }
    if (fs::path(imu).has_parent_path())
        return Unexpected(
            derr(DatasetErrorCode::UnsafePath, imu, "IMU file must be in the folder"));
    auto text = read_text_file(dir / imu, imu, open_opts.limits.max_csv_bytes);
    if (!text) return Unexpected(text.error());
    auto lines = parse_imu(*text, imu);
    if (!lines) return Unexpected(lines.error());
    if (images.empty())
        return Unexpected(derr(DatasetErrorCode::Missing, dir.string(), "no image files"));
    if (lines->size() != images.size())
        return Unexpected(derr(DatasetErrorCode::Inconsistent, imu,
                               std::to_string(lines->size()) + " lines but the folder holds " +
                                   std::to_string(images.size()) + " images"));
    if (static_cast<std::int64_t>(images.size()) > open_opts.limits.max_frames)
        return Unexpected(derr(DatasetErrorCode::OutOfRange, dir.string(), "too many images"));
    std::sort(images.begin(), images.end(), natural_less);

    cv::Mat first = cv::imread((dir / images.front()).string(), cv::IMREAD_COLOR);
    if (first.empty())
        return Unexpected(
            derr(DatasetErrorCode::Malformed, images.front(), "not a decodable image"));
    DatasetInfo info;
    info.camera = opts.camera;
    info.width = first.cols;
    info.height = first.rows;
    if (info.width > open_opts.limits.max_dimension || info.height > open_opts.limits.max_dimension)
        return Unexpected(derr(DatasetErrorCode::OutOfRange, images.front(), "image too large"));
    info.fps = opts.fps;
    info.frames = static_cast<std::int64_t>(images.size());
    info.images = ".";
    info.source = "imported";
    auto cal = default_calibration(opts.camera, open_opts.assets_dir);
    if (!cal) return Unexpected(cal.error());
    std::vector<FrameRow> rows;
    std::vector<fs::path> paths;
    rows.reserve(images.size());
    for (std::size_t i = 0; i < images.size(); ++i) {
        FrameRow r;
        r.frame = static_cast<std::int64_t>(i);
        r.nav.t_ns = std::llround(static_cast<double>(i) * 1e9 / opts.fps);
        const ImuLine& l = (*lines)[i];
        r.nav.roll_deg = l.roll;
        r.nav.pitch_deg = l.pitch;
        r.nav.yaw_deg = l.yaw;
        r.nav.vx_mps = l.vx;
        r.nav.vy_mps = l.vy;
        rows.push_back(r);
        paths.push_back(dir / images[i]);
    }
    return Dataset::from_parts(dir, info, scaled_to(*cal, info.width, info.height), std::move(rows),
                               std::move(paths));
}

Expected<Dataset, DatasetError> import_thesis(const fs::path& src, const fs::path& dst,
                                              const ThesisImportOptions& opts,
                                              const DatasetOpenOptions& open_opts) {
    auto d = open_thesis_folder(src, opts, open_opts);
    if (!d) return Unexpected(d.error());
    std::error_code ec;
    if (fs::exists(dst, ec) && (!fs::is_directory(dst, ec) || !fs::is_empty(dst, ec)))
        return Unexpected(
            derr(DatasetErrorCode::Io, dst.string(), "exists and is not an empty directory"));
    fs::create_directories(dst / "frames", ec);
    if (ec) return Unexpected(derr(DatasetErrorCode::Io, dst.string(), ec.message()));
    std::string frames = frames_csv_header();
    for (std::size_t i = 0; i < d->frames().size(); ++i) {
        const fs::path& from = d->image_files()[i];
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
                    derr(DatasetErrorCode::Io, from.filename().string(), "cannot convert to PNG"));
        } else {
            fs::copy_file(from, dst / "frames" / (name + ext), ec);
            if (ec)
                return Unexpected(
                    derr(DatasetErrorCode::Io, from.filename().string(), ec.message()));
        }
        frames += frames_csv_row(d->frames()[i]);
    }
    DatasetInfo info = d->info();
    info.images = "frames";
    if (auto e = write_file_atomic(dst / "frames.csv", frames, "frames.csv")) return Unexpected(*e);
    if (auto e = write_file_atomic(dst / "flight.json", flight_json_text(info), "flight.json"))
        return Unexpected(*e);
    return Dataset::open(dst, open_opts);
}

std::optional<DatasetError> export_thesis(const Dataset& d, FrameStore& frames,
                                          const fs::path& dst) {
    std::error_code ec;
    if (fs::exists(dst, ec) && (!fs::is_directory(dst, ec) || !fs::is_empty(dst, ec)))
        return derr(DatasetErrorCode::Io, dst.string(), "exists and is not an empty directory");
    fs::create_directories(dst, ec);
    if (ec) return derr(DatasetErrorCode::Io, dst.string(), ec.message());
    std::string imu;
    cv::Mat img;
    auto num = [](double v) { return std::isnan(v) ? std::string("nan") : csv::format_number(v); };
    for (std::int64_t i = 0; i < d.frame_count(); ++i) {
        if (auto e = frames.read(i, img)) return e;
        char name[32];
        std::snprintf(name, sizeof name, "%06lld.png", static_cast<long long>(i));
        if (!cv::imwrite((dst / name).string(), img))
            return derr(DatasetErrorCode::Io, name, "cannot write image");
        const NavState& s = d.frames()[static_cast<std::size_t>(i)].nav;
        imu += num(s.roll_deg) + ' ' + num(s.pitch_deg) + ' ' + num(s.yaw_deg) + ' ' +
               num(s.vx_mps) + ' ' + num(s.vy_mps) + '\n';
    }
    return write_file_atomic(dst / "imu.txt", imu, "imu.txt");
}

}  // namespace gs
