#include "vision/calibration.hpp"
#include "drone/core/unknown.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <numeric>

namespace gs::vision {

namespace {

constexpr int kMaxBoardSide = 100;

cv::Mat to_grey(const cv::Mat& image) {
    cv::Mat grey;
    if (image.channels() == 3) {
        cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
    } else if (image.channels() == 4) {
        cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
    } else {
        grey = image;
    }
    if (grey.depth() != CV_8U) {
        cv::Mat g8;
        cv::normalize(grey, g8, 0, 255, cv::NORM_MINMAX, CV_8U);
        grey = g8;
    }
    return grey;
}

// Smallest distance between neighbouring corners along rows and columns.
double min_corner_spacing(std::span<const cv::Point2f> c, const BoardSpec& b) {
    double best = DBL_MAX;
    for (int r = 0; r < b.rows; ++r) {
        for (int k = 0; k < b.cols; ++k) {
            const auto i = static_cast<std::size_t>(r * b.cols + k);
            if (k + 1 < b.cols) best = std::min(best, cv::norm(c[i + 1] - c[i]));
            if (r + 1 < b.rows) {
                best = std::min(best, cv::norm(c[i + static_cast<std::size_t>(b.cols)] - c[i]));
            }
        }
    }
    return best;
}

double median_of(std::vector<double> v) {
    if (v.empty()) return kUnknown;
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    if (v.size() % 2 == 1) return *mid;
    const double hi = *mid;
    const double lo = *std::max_element(v.begin(), mid);
    return 0.5 * (lo + hi);
}

double rms_of(std::span<const cv::Point2f> a, std::span<const cv::Point2f> b) {
    double s = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const double dx = static_cast<double>(a[i].x) - static_cast<double>(b[i].x);
        const double dy = static_cast<double>(a[i].y) - static_cast<double>(b[i].y);
        s += dx * dx + dy * dy;
    }
    return a.empty() ? 0.0 : std::sqrt(s / static_cast<double>(a.size()));
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Board

bool BoardSpec::valid() const {
    return cols >= 3 && rows >= 3 && cols <= kMaxBoardSide && rows <= kMaxBoardSide &&
           std::isfinite(square_m) && square_m > 0;
}

std::vector<cv::Point3f> BoardSpec::object_points() const {
    std::vector<cv::Point3f> p;
    p.reserve(static_cast<std::size_t>(corner_count()));
    for (int r = 0; r < rows; ++r) {
        for (int c = 0; c < cols; ++c) {
            p.emplace_back(static_cast<float>(c * square_m), static_cast<float>(r * square_m), 0.f);
        }
    }
    return p;
}

std::optional<cv::Size> parse_board_size(std::string_view text) {
    const auto sep = text.find_first_of("xX*");
    if (sep == std::string_view::npos) return std::nullopt;
    auto parse = [](std::string_view s, int& out) {
        if (s.empty()) return false;
        const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
        return r.ec == std::errc{} && r.ptr == s.data() + s.size();
    };
    int c = 0, r = 0;
    if (!parse(text.substr(0, sep), c) || !parse(text.substr(sep + 1), r)) return std::nullopt;
    if (c < 3 || r < 3 || c > kMaxBoardSide || r > kMaxBoardSide) return std::nullopt;
    return cv::Size(c, r);
}

const char* to_string(DetectStatus s) {
    switch (s) {
        case DetectStatus::Found:
            return "found";
        case DetectStatus::NotFound:
            return "board not found";
        case DetectStatus::Blurry:
            return "board blurry";
        case DetectStatus::EmptyImage:
            return "empty image";
    }
    return "?";
}

BoardDetection detect_board(const cv::Mat& image, const BoardSpec& board,
                            const DetectOptions& opts) {
    BoardDetection d;
    if (image.empty() || !board.valid()) {
        d.status = image.empty() ? DetectStatus::EmptyImage : DetectStatus::NotFound;
        return d;
    }
    d.image_size = image.size();
    const cv::Mat grey = to_grey(image);
    const cv::Size pattern = board.pattern_size();
    int flags = cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE;
    if (opts.fast_check) flags |= cv::CALIB_CB_FAST_CHECK;

    bool found = false;
    try {
        found = cv::findChessboardCorners(grey, pattern, d.corners, flags);
        if (found) {
            // The search window must stay inside the corner's own squares: a fixed 11×11 window
            // pulls corners of small, distant boards towards their neighbours (2 px RMS on
            // rjw57 frame0002 instead of 0.29).
            const double spacing = min_corner_spacing(d.corners, board);
            const int half = std::clamp(static_cast<int>(spacing / 3.0), 2, 8);
            cv::cornerSubPix(
                grey, d.corners, cv::Size(half, half), cv::Size(-1, -1),
                cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-3));
        } else if (opts.sb_fallback) {
            found = cv::findChessboardCornersSB(grey, pattern, d.corners,
                                                cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY);
        }
        if (found) d.sharpness_px = cv::estimateChessboardSharpness(grey, pattern, d.corners)[0];
    } catch (const cv::Exception&) {
        found = false;  // OpenCV rejects odd inputs by throwing; for us that is "not found"
    }
    if (!found || static_cast<int>(d.corners.size()) != board.corner_count()) {
        d.corners.clear();
        d.status = DetectStatus::NotFound;
        return d;
    }
    d.status = (std::isfinite(d.sharpness_px) && d.sharpness_px > opts.max_blur_px)
                   ? DetectStatus::Blurry
                   : DetectStatus::Found;
    return d;
}

// ---------------------------------------------------------------------------------------------
// Coverage

CoverageMap::CoverageMap(cv::Size image_size, int grid_cols, int grid_rows)
    : image_size_(image_size),
      cols_(std::max(grid_cols, 1)),
      rows_(std::max(grid_rows, 1)),
      counts_(static_cast<std::size_t>(cols_ * rows_), 0) {}

cv::Rect2d CoverageMap::cell_rect(int col, int row) const {
    const double w = static_cast<double>(image_size_.width) / cols_;
    const double h = static_cast<double>(image_size_.height) / rows_;
    return {col * w, row * h, w, h};
}

std::vector<int> CoverageMap::cells_of(std::span<const cv::Point2f> corners) const {
    std::vector<int> cells;
    if (corners.size() < 3 || counts_.empty()) return cells;
    std::vector<cv::Point2f> hull;
    cv::convexHull(std::vector<cv::Point2f>(corners.begin(), corners.end()), hull);
    for (int r = 0; r < rows_; ++r) {
        for (int c = 0; c < cols_; ++c) {
            const cv::Rect2d rc = cell_rect(c, r);
            const cv::Point2f centre(static_cast<float>(rc.x + rc.width / 2),
                                     static_cast<float>(rc.y + rc.height / 2));
            if (cv::pointPolygonTest(hull, centre, false) >= 0) cells.push_back(r * cols_ + c);
        }
    }
    return cells;
}

int CoverageMap::new_cells(std::span<const cv::Point2f> corners) const {
    int n = 0;
    for (int i : cells_of(corners)) n += counts_[static_cast<std::size_t>(i)] == 0 ? 1 : 0;
    return n;
}

void CoverageMap::add(std::span<const cv::Point2f> corners) {
    if (counts_.empty()) return;
    for (int i : cells_of(corners)) ++counts_[static_cast<std::size_t>(i)];
    const double cx = image_size_.width / 2.0, cy = image_size_.height / 2.0;
    const double half_diag = std::hypot(cx, cy);
    for (const auto& p : corners) {
        const double r = std::hypot(static_cast<double>(p.x) - cx, static_cast<double>(p.y) - cy);
        max_radius_ = std::max(max_radius_, std::min(1.0, r / half_diag));
    }
    ++views_;
}

int CoverageMap::count(int col, int row) const {
    if (col < 0 || row < 0 || col >= cols_ || row >= rows_) return 0;
    return counts_[static_cast<std::size_t>(row * cols_ + col)];
}

double CoverageMap::fraction() const {
    if (counts_.empty()) return 0;
    const auto covered = std::count_if(counts_.begin(), counts_.end(), [](int n) { return n > 0; });
    return static_cast<double>(covered) / static_cast<double>(counts_.size());
}

bool CoverageMap::in_corner_region(int col, int row) const {
    const cv::Rect2d rc = cell_rect(col, row);
    const double x = rc.x + rc.width / 2, y = rc.y + rc.height / 2;
    const double w = image_size_.width, h = image_size_.height;
    return (x < w / 4 || x > 3 * w / 4) && (y < h / 4 || y > 3 * h / 4);
}

int CoverageMap::corner_regions_covered() const {
    std::array<bool, 4> hit{};
    for (int r = 0; r < rows_; ++r) {
        for (int c = 0; c < cols_; ++c) {
            if (count(c, r) == 0 || !in_corner_region(c, r)) continue;
            const cv::Rect2d rc = cell_rect(c, r);
            const bool right = rc.x + rc.width / 2 > image_size_.width / 2.0;
            const bool bottom = rc.y + rc.height / 2 > image_size_.height / 2.0;
            hit[static_cast<std::size_t>((bottom ? 2 : 0) + (right ? 1 : 0))] = true;
        }
    }
    return static_cast<int>(std::count(hit.begin(), hit.end(), true));
}

// ---------------------------------------------------------------------------------------------
// Calibration

int CalibrationResult::used_views() const {
    return static_cast<int>(std::count(view_used.begin(), view_used.end(), true));
}

CalibrationInfo CalibrationResult::info() const {
    CalibrationInfo i;
    i.rms_px = rms_px;
    i.std_dev = std_dev;
    i.views = used_views();
    return i;
}

Expected<CalibrationResult, CalibrationError> calibrate_views(
    std::span<const std::vector<cv::Point2f>> views, const BoardSpec& board, cv::Size image_size,
    const CalibrationOptions& opts) {
    if (!board.valid()) {
        return calibration_error(
            CalibrationErrorKind::BadBoardSpec,
            "the board needs at least 3×3 inner corners and a positive square size");
    }
    if (image_size.width <= 0 || image_size.height <= 0) {
        return calibration_error(CalibrationErrorKind::NoImages, "no image size");
    }
    const int min_views = std::max(opts.min_views, 1);
    if (static_cast<int>(views.size()) < min_views) {
        return calibration_error(CalibrationErrorKind::TooFewViews,
                                 std::to_string(views.size()) +
                                     " view(s) with the board, at least " +
                                     std::to_string(min_views) + " needed");
    }
    for (std::size_t i = 0; i < views.size(); ++i) {
        if (static_cast<int>(views[i].size()) != board.corner_count()) {
            return calibration_error(CalibrationErrorKind::BadBoardSpec,
                                     "view " + std::to_string(i) + " has " +
                                         std::to_string(views[i].size()) + " corners, the board " +
                                         std::to_string(board.corner_count()));
        }
    }

    const std::vector<cv::Point3f> obj = board.object_points();
    std::vector<int> active(views.size());
    std::iota(active.begin(), active.end(), 0);
    const auto max_rejected =
        static_cast<std::size_t>(opts.max_rejected_fraction * static_cast<double>(views.size()));
    const int flags = opts.fix_k3 ? cv::CALIB_FIX_K3 : 0;

    CalibrationResult res;
    cv::Mat k, d, sd_intr, sd_extr, per_view;
    for (;;) {
        std::vector<std::vector<cv::Point3f>> op(active.size(), obj);
        std::vector<std::vector<cv::Point2f>> ip;
        ip.reserve(active.size());
        for (int i : active) ip.push_back(views[static_cast<std::size_t>(i)]);
        std::vector<cv::Mat> rvecs, tvecs;
        try {
            res.rms_px = cv::calibrateCamera(
                op, ip, image_size, k, d, rvecs, tvecs, sd_intr, sd_extr, per_view, flags,
                cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100,
                                 DBL_EPSILON));
        } catch (const cv::Exception& e) {
            return calibration_error(CalibrationErrorKind::CalibrationFailed, e.what());
        }
        if (!std::isfinite(res.rms_px) || !cv::checkRange(k) || !cv::checkRange(d) ||
            k.at<double>(0, 0) <= 0 || k.at<double>(1, 1) <= 0) {
            return calibration_error(
                CalibrationErrorKind::CalibrationFailed,
                "the optimiser did not converge (views too similar or corners wrong?)");
        }
        if (active.size() <= static_cast<std::size_t>(min_views) ||
            res.rejected.size() >= max_rejected) {
            break;
        }
        std::vector<double> errs(per_view.begin<double>(), per_view.end<double>());
        const double med = median_of(errs);
        std::vector<double> dev(errs.size());
        for (std::size_t i = 0; i < errs.size(); ++i) dev[i] = std::abs(errs[i] - med);
        const double mad = median_of(dev);
        const double threshold =
            std::max(med + opts.outlier_mad_k * 1.4826 * mad, opts.outlier_min_ratio * med);
        const auto worst =
            static_cast<std::size_t>(std::max_element(errs.begin(), errs.end()) - errs.begin());
        if (errs[worst] <= threshold) break;
        res.rejected.push_back(active[worst]);
        active.erase(active.begin() + static_cast<std::ptrdiff_t>(worst));
    }

    CameraCalibration& cam = res.camera;
    cam.width = image_size.width;
    cam.height = image_size.height;
    cam.fx = k.at<double>(0, 0);
    cam.fy = k.at<double>(1, 1);
    cam.cx = k.at<double>(0, 2);
    cam.cy = k.at<double>(1, 2);
    for (std::size_t i = 0; i < 5; ++i) {
        cam.dist[i] = i < d.total() ? d.at<double>(static_cast<int>(i)) : 0.0;
    }
    for (std::size_t i = 0; i < 9; ++i) {
        res.std_dev[i] = i < sd_intr.total() ? sd_intr.at<double>(static_cast<int>(i)) : kUnknown;
    }

    res.view_used.assign(views.size(), false);
    res.view_rms_px.assign(views.size(), kUnknown);
    for (std::size_t a = 0; a < active.size(); ++a) {
        const auto i = static_cast<std::size_t>(active[a]);
        res.view_used[i] = true;
        res.view_rms_px[i] = per_view.at<double>(static_cast<int>(a));
    }
    const cv::Matx33d km = cam.camera_matrix();
    const cv::Vec<double, 5> dm = cam.dist_coeffs();
    for (int i : res.rejected) {
        const auto& v = views[static_cast<std::size_t>(i)];
        cv::Vec3d rvec, tvec;
        try {
            if (cv::solvePnP(obj, v, km, dm, rvec, tvec)) {
                std::vector<cv::Point2f> proj;
                cv::projectPoints(obj, rvec, tvec, km, dm, proj);
                res.view_rms_px[static_cast<std::size_t>(i)] = rms_of(proj, v);
            }
        } catch (const cv::Exception&) {
            // stays NaN: the view could not even be posed
        }
    }
    res.coverage = CoverageMap(image_size);
    for (int i : active) res.coverage.add(views[static_cast<std::size_t>(i)]);
    return res;
}

double max_line_deviation_px(std::span<const cv::Point2f> corners, const BoardSpec& board) {
    if (static_cast<int>(corners.size()) != board.corner_count()) {
        return kUnknown;
    }
    double worst = 0;
    auto line_dev = [&worst](const std::vector<cv::Point2f>& pts) {
        cv::Vec4f l;  // (vx, vy, x0, y0), unit direction
        cv::fitLine(pts, l, cv::DIST_L2, 0, 1e-6, 1e-6);
        for (const auto& p : pts) {
            const double dx = static_cast<double>(p.x) - static_cast<double>(l[2]);
            const double dy = static_cast<double>(p.y) - static_cast<double>(l[3]);
            worst = std::max(
                worst, std::abs(dx * static_cast<double>(l[1]) - dy * static_cast<double>(l[0])));
        }
    };
    std::vector<cv::Point2f> pts;
    for (int r = 0; r < board.rows; ++r) {
        pts.clear();
        for (int c = 0; c < board.cols; ++c)
            pts.push_back(corners[static_cast<std::size_t>(r * board.cols + c)]);
        line_dev(pts);
    }
    for (int c = 0; c < board.cols; ++c) {
        pts.clear();
        for (int r = 0; r < board.rows; ++r)
            pts.push_back(corners[static_cast<std::size_t>(r * board.cols + c)]);
        line_dev(pts);
    }
    return worst;
}

std::vector<cv::Point2f> undistort_corners(std::span<const cv::Point2f> corners,
                                           const CameraCalibration& cam) {
    std::vector<cv::Point2f> out;
    if (corners.empty()) return out;
    const std::vector<cv::Point2f> in(corners.begin(), corners.end());
    const cv::Matx33d k = cam.camera_matrix();
    cv::undistortPoints(
        in, out, k, cam.dist_coeffs(), cv::noArray(), k,
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-9));
    return out;
}

// ---------------------------------------------------------------------------------------------
// Session

const char* to_string(FrameStatus s) {
    switch (s) {
        case FrameStatus::Accepted:
            return "accepted";
        case FrameStatus::NotFound:
            return "board not found";
        case FrameStatus::Blurry:
            return "board blurry";
        case FrameStatus::EmptyImage:
            return "empty image";
        case FrameStatus::SizeMismatch:
            return "image size differs from the first image";
        case FrameStatus::NoNewCoverage:
            return "adds no coverage";
    }
    return "?";
}

CalibrationSession::CalibrationSession(BoardSpec board, SessionOptions opts)
    : board_(board), opts_(opts) {}

namespace {

// What a detection means for a view: only a found board goes on to the coverage checks.
FrameStatus frame_status(DetectStatus d) {
    switch (d) {
        case DetectStatus::EmptyImage:
            return FrameStatus::EmptyImage;
        case DetectStatus::NotFound:
            return FrameStatus::NotFound;
        case DetectStatus::Blurry:
            return FrameStatus::Blurry;
        case DetectStatus::Found:
            break;
    }
    return FrameStatus::Accepted;
}

}  // namespace

ViewResult CalibrationSession::check(const cv::Mat& image) const {
    ViewResult fr;
    if (image_size_ && !image.empty() && image.size() != *image_size_) {
        fr.status = FrameStatus::SizeMismatch;
        fr.detection.image_size = image.size();
        return fr;
    }
    fr.detection = detect_board(image, board_, opts_.detect);
    fr.status = frame_status(fr.detection.status);
    if (fr.status != FrameStatus::Accepted) return fr;
    fr.new_cells = coverage_.views() > 0
                       ? coverage_.new_cells(fr.detection.corners)
                       : CoverageMap(image.size(), opts_.grid_cols, opts_.grid_rows)
                             .new_cells(fr.detection.corners);
    return fr;
}

ViewResult CalibrationSession::add_frame(const cv::Mat& image, bool require_new_coverage) {
    ViewResult fr = check(image);
    if (fr.status != FrameStatus::Accepted) return fr;
    return add_detection(fr.detection, require_new_coverage);
}

ViewResult CalibrationSession::add_detection(const BoardDetection& detection,
                                             bool require_new_coverage) {
    ViewResult fr;
    fr.detection = detection;
    fr.status = frame_status(detection.status);
    if (fr.status != FrameStatus::Accepted) return fr;
    if (static_cast<int>(detection.corners.size()) != board_.corner_count()) {
        fr.status = FrameStatus::NotFound;
        return fr;
    }
    if (image_size_ && detection.image_size != *image_size_) {
        fr.status = FrameStatus::SizeMismatch;
        return fr;
    }
    if (!image_size_) {
        image_size_ = detection.image_size;
        coverage_ = CoverageMap(*image_size_, opts_.grid_cols, opts_.grid_rows);
    }
    fr.new_cells = coverage_.new_cells(detection.corners);
    if (require_new_coverage && !views_.empty() && fr.new_cells == 0) {
        fr.status = FrameStatus::NoNewCoverage;
        return fr;
    }
    views_.push_back(detection.corners);
    coverage_.add(detection.corners);
    fr.status = FrameStatus::Accepted;
    if (opts_.recalibrate_on_add) recalibrate_if_enough();
    return fr;
}

void CalibrationSession::recalibrate_if_enough() {
    if (static_cast<int>(views_.size()) < opts_.calibration.min_views) {
        result_.reset();
        return;
    }
    (void)calibrate();
}

Expected<CalibrationResult, CalibrationError> CalibrationSession::calibrate() {
    if (!image_size_) {
        last_error_ = CalibrationError{CalibrationErrorKind::BoardNotFound, "no view kept yet"};
        return Unexpected(*last_error_);
    }
    auto r = calibrate_views(views_, board_, *image_size_, opts_.calibration);
    if (r) {
        result_ = *r;
        last_error_.reset();
    } else {
        last_error_ = r.error();
    }
    return r;
}

double CalibrationSession::rms_px() const {
    return result_ ? result_->rms_px : kUnknown;
}

void CalibrationSession::rebuild_coverage() {
    if (!image_size_) return;
    coverage_ = CoverageMap(*image_size_, opts_.grid_cols, opts_.grid_rows);
    for (const auto& v : views_) coverage_.add(v);
}

void CalibrationSession::remove_last_view() {
    if (views_.empty()) return;
    views_.pop_back();
    if (views_.empty()) {
        reset();
        return;
    }
    rebuild_coverage();
    recalibrate_if_enough();
}

void CalibrationSession::reset() {
    views_.clear();
    image_size_.reset();
    coverage_ = CoverageMap();
    result_.reset();
    last_error_.reset();
}

Expected<void, CalibrationError> CalibrationSession::save(const std::string& path,
                                                          CalibrationInfo info,
                                                          std::string source) const {
    if (!result_) {
        return calibration_error(CalibrationErrorKind::TooFewViews,
                                 "no calibration yet: " + std::to_string(views_.size()) +
                                     " view(s) kept, " +
                                     std::to_string(opts_.calibration.min_views) + " needed");
    }
    const CalibrationInfo numbers = result_->info();
    info.rms_px = numbers.rms_px;
    info.std_dev = numbers.std_dev;
    info.views = numbers.views;
    CameraCalibration camera = result_->camera;
    camera.source = std::move(source);
    if (auto saved = save_calibration_file(path, camera, info); !saved)
        return calibration_error(CalibrationErrorKind::FileWrite, to_string(saved.error()));
    return {};
}

const char* to_string(CalibrationErrorKind k) {
    switch (k) {
        case CalibrationErrorKind::NoImages:
            return "no images";
        case CalibrationErrorKind::ImageUnreadable:
            return "image unreadable";
        case CalibrationErrorKind::ImageSizeMismatch:
            return "image size mismatch";
        case CalibrationErrorKind::BoardNotFound:
            return "board not found";
        case CalibrationErrorKind::TooFewViews:
            return "too few views";
        case CalibrationErrorKind::BadBoardSpec:
            return "bad board";
        case CalibrationErrorKind::CalibrationFailed:
            return "calibration failed";
        case CalibrationErrorKind::FileWrite:
            return "cannot write file";
    }
    return "unknown calibration error";
}

std::string CalibrationError::message() const {
    return detail.empty() ? std::string(to_string(kind))
                          : std::string(to_string(kind)) + ": " + detail;
}

}  // namespace gs::vision
