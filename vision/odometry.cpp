#include "vision/odometry.hpp"
#include "drone/core/geometry.hpp"
#include "vision/common.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

namespace gs::vision {
namespace {

bool finite(double v) {
    return std::isfinite(v);
}

// The image axes (x right, y down) on the body's horizontal axes (forward, right): the top-left
// block of body_from_camera, exact for cameras looking straight down or up.
geom::Mat2 mount_axes(CameraMount m) {
    return geom::body_from_camera(m).topLeftCorner<2, 2>();
}

// Pixel space of the focal length: H_n = F^-1 H F (eq. 3.14 on the whole mapping).
geom::Mat3 focal_scale(double fx_px, double fy_px) {
    return geom::Vec3(fx_px, fy_px, 1).asDiagonal();
}

}  // namespace

double wrap_deg(double a) {
    if (!finite(a)) return a;
    a = std::fmod(a + 180.0, 360.0);
    if (a < 0) a += 360.0;
    return a - 180.0;
}

// ---- Pure pieces ----------------------------------------------------------------------------

HomographyParts decompose_homography(const cv::Matx33d& h) {
    HomographyParts p;
    const double h33 = h(2, 2);
    if (!finite(h33) || h33 == 0.0) return p;
    const cv::Matx33d n = h * (1.0 / h33);
    p.r = {n(0, 0), n(0, 1), n(1, 0), n(1, 1)};
    p.t = {n(0, 2), n(1, 2)};
    p.s = {n(2, 0), n(2, 1)};
    p.angle_rad = std::atan2(p.r(1, 0), p.r(0, 0));
    p.ok = finite(p.angle_rad) && finite(p.t[0]) && finite(p.t[1]);
    return p;
}

cv::Vec2d pixels_to_metres(cv::Vec2d t_px, double fx_px, double fy_px, double distance_m) {
    return {t_px[0] / fx_px * distance_m, t_px[1] / fy_px * distance_m};
}

double focal_length_px(double focal_length, double sensor_size, int resolution_px) {
    // Eq. 3.15 as printed (F = f W / w) has the ratio inverted: a focal length in pixels is the
    // focal length over the size of one pixel, f / (W / w).
    return focal_length * resolution_px / sensor_size;
}

const char* to_string(CameraMount m) {
    switch (m) {
        case CameraMount::Front:
            return "front";
        case CameraMount::Bottom:
            return "bottom";
        case CameraMount::Top:
            return "top";
    }
    return "?";
}

BodyMotion body_motion_from_homography(const cv::Matx33d& h_px, double fx_px, double fy_px,
                                       double distance_m, CameraMount mount) {
    // Normalised image coordinates: H_n = F^-1 H F (eq. 3.14 applied to the whole mapping, so the
    // rotation block is free of the pixel aspect ratio too).
    const geom::Mat3 f = focal_scale(fx_px, fy_px);
    const geom::Mat3 f_inv = focal_scale(1 / fx_px, 1 / fy_px);
    const HomographyParts p = decompose_homography(geom::to_cv(f_inv * geom::from_cv(h_px) * f));
    BodyMotion m;
    if (!p.ok) return m;
    const geom::Mat2 a = mount_axes(mount);
    m.r_body = geom::to_cv(a * geom::from_cv(p.r) * a.transpose());
    const geom::Vec2 t_body = a * (geom::Vec2(p.t[0], p.t[1]) * distance_m);
    // Floor points move by the inverse of the camera's motion: x_i = R x_{i-1} - R_i^T dC.
    m.forward_m = -t_body.x();
    m.right_m = -t_body.y();
    m.yaw_deg = -std::atan2(m.r_body(1, 0), m.r_body(0, 0)) / kRadPerDeg;
    return m;
}

BodyMotion combine_motions(const BodyMotion& a, const BodyMotion& b) {
    BodyMotion m;
    m.forward_m = (a.forward_m + b.forward_m) / 2;
    m.right_m = (a.right_m + b.right_m) / 2;
    m.r_body = (a.r_body + b.r_body) * 0.5;
    m.yaw_deg = -std::atan2(m.r_body(1, 0), m.r_body(0, 0)) / kRadPerDeg;
    return m;
}

// ---- Filters --------------------------------------------------------------------------------

FilteredMotion OdometryFilter::apply(double forward_m, double right_m, double yaw_deg) {
    FilteredMotion o{forward_m, right_m, yaw_deg, false, false};
    if (p_.spike_filter &&
        (std::abs(forward_m) > p_.spike_translation_m ||
         std::abs(right_m) > p_.spike_translation_m || std::abs(yaw_deg) > p_.spike_rotation_deg)) {
        o = {0, 0, 0, true, false};
    } else if (p_.rotation_gate && std::abs(yaw_deg) > p_.rotation_gate_deg) {
        o.forward_m = o.right_m = 0;
        o.rotation_gated = true;
    }
    const int n = std::clamp(p_.smoothing_samples, 1, kMaxSmoothing);
    if (n > 1) {
        fx_[next_] = o.forward_m;
        fy_[next_] = o.right_m;
        next_ = (next_ + 1) % n;
        count_ = std::min(count_ + 1, n);
        double sx = 0, sy = 0;
        for (int i = 0; i < count_; ++i) {
            sx += fx_[i];
            sy += fy_[i];
        }
        o.forward_m = sx / count_;
        o.right_m = sy / count_;
    }
    return o;
}

const PlanarPose& TrajectoryIntegrator::add(double forward_m, double right_m, double yaw_deg) {
    pose_.yaw_deg += yaw_deg;
    const geom::Vec2 step =
        geom::world_from_heading(pose_.yaw_deg) * geom::Vec2(forward_m, right_m);
    pose_.x_m += step.x();
    pose_.y_m += step.y();
    return pose_;
}

// ---- Parameters -----------------------------------------------------------------------------

const char* to_string(YawSource s) {
    switch (s) {
        case YawSource::Visual:
            return "visual";
        case YawSource::Navdata:
            return "navdata";
        case YawSource::Fused:
            return "fused";
    }
    return "?";
}

std::optional<YawSource> yaw_source_from_string(const std::string& s) {
    if (s == "visual") return YawSource::Visual;
    if (s == "navdata") return YawSource::Navdata;
    if (s == "fused") return YawSource::Fused;
    return std::nullopt;
}

const char* to_string(CameraStatus s) {
    switch (s) {
        case CameraStatus::Ok:
            return "ok";
        case CameraStatus::First:
            return "first frame";
        case CameraStatus::NoDistance:
            return "no distance";
        case CameraStatus::TooFewPoints:
            return "too few tracked points";
        case CameraStatus::NoHomography:
            return "no homography";
        case CameraStatus::TooFewInliers:
            return "too few inliers";
    }
    return "?";
}

const ParamTable<OdometryParams>& odometry_param_table() {
    static const ParamTable<OdometryParams> t = [] {
        using P = OdometryParams;
        ParamTable<P> tab;
        tab.add("odo.max_corners", &P::max_corners, 8, 5000, "Shi-Tomasi corners per frame")
            .add("odo.quality_level", &P::quality_level, 1e-4, 0.5,
                 "Shi-Tomasi strength relative to the strongest corner")
            .add("odo.min_corner_distance_px", &P::min_corner_distance_px, 1, 100,
                 "minimum distance between corners")
            .add("odo.block_size", &P::block_size, 3, 15, "Shi-Tomasi window")
            .add("odo.lk_window_px", &P::lk_window_px, 5, 81, "Lucas-Kanade window")
            .add("odo.lk_levels", &P::lk_levels, 0, 6, "Lucas-Kanade pyramid levels")
            .add("odo.lk_iterations", &P::lk_iterations, 1, 100, "Lucas-Kanade iterations")
            .add("odo.lk_epsilon", &P::lk_epsilon, 1e-4, 1, "Lucas-Kanade convergence (px)")
            .add("odo.ransac_threshold_px", &P::ransac_threshold_px, 0.1, 20,
                 "RANSAC reprojection threshold (eq. 3.12)")
            .add("odo.min_inliers", &P::min_inliers, 4, 1000,
                 "fewer homography inliers: no estimate from that camera")
            .add("odo.centre_on_principal_point", &P::centre_on_principal_point, 0, 1,
                 "homography about the principal point (thesis: pixel origin)")
            .add("odo.undistort", &P::undistort, 0, 1, "undistort points first")
            .add("odo.image_tilt", &P::image_tilt, 0, 1,
                 "correct the tilt change from the homography's projective part (floor plane)")
            .add("odo.image_tilt_sigma_deg", &P::image_tilt_sigma_deg, 0.001, 10,
                 "image tilt: its standard error per sample")
            .add("odo.nav_tilt_sigma_deg", &P::nav_tilt_sigma_deg, 0.001, 10,
                 "image tilt: the navdata roll/pitch change's standard error per sample")
            .add("odo.image_tilt_max_deg", &P::image_tilt_max_deg, 0.01, 45,
                 "image tilt: a larger correction is not believed (the points are not a floor)")
            .add("odo.tilt_compensation", &P::tilt_compensation, 0, 1,
                 "derotate points by navdata roll/pitch")
            .add("odo.yaw_fusion_weight", &P::yaw_fusion_weight, 0, 1,
                 "navdata share of the rotation when the yaw source is fused")
            .add("filter.spike_filter", &P::spike_filter, 0, 1,
                 "zero a sample over the spike bounds (eq. 3.20)")
            .add("filter.spike_translation_m", &P::spike_translation_m, 0.001, 10,
                 "spike bound on x and y per sample")
            .add("filter.spike_rotation_deg", &P::spike_rotation_deg, 0.01, 180,
                 "spike bound on rotation per sample")
            .add("filter.rotation_gate", &P::rotation_gate, 0, 1,
                 "zero the translation while rotating")
            .add("filter.rotation_gate_deg", &P::rotation_gate_deg, 0.01, 180,
                 "rotation per sample above which translation is zeroed")
            .add("filter.smoothing_samples", &P::smoothing_samples, 1,
                 OdometryFilter::kMaxSmoothing, "moving average of x and y (eq. 3.19: 4)");
        return tab;
    }();
    return t;
}

// ---- Per-camera estimator -------------------------------------------------------------------

namespace {

class CameraOdometry {
public:
    CameraOdometry(const CameraCalibration& calib, CameraMount mount, const OdometryParams& p)
        : calib_(calib), mount_(mount), p_(p) {}

    void reset() { have_prev_ = false; }

    CameraEstimate process(const cv::Mat& image, double distance_m, double roll_deg,
                           double pitch_deg) {
        CameraEstimate e;
        auto t0 = std::chrono::steady_clock::now();
        double level_roll = roll_deg, level_pitch = pitch_deg;  // this frame's levelling
        if (image.channels() == 3)
            cv::cvtColor(image, grey_, cv::COLOR_BGR2GRAY);
        else if (image.channels() == 4)
            cv::cvtColor(image, grey_, cv::COLOR_BGRA2GRAY);
        else
            image.copyTo(grey_);

        if (have_prev_ && !prev_corners_.empty()) {
            const cv::TermCriteria crit(cv::TermCriteria::COUNT | cv::TermCriteria::EPS,
                                        p_.lk_iterations, p_.lk_epsilon);
            cv::calcOpticalFlowPyrLK(prev_grey_, grey_, prev_corners_, cur_pts_, status_, err_,
                                     cv::Size(p_.lk_window_px, p_.lk_window_px), p_.lk_levels,
                                     crit);
            src_.clear();
            dst_.clear();
            const float w = static_cast<float>(grey_.cols), h = static_cast<float>(grey_.rows);
            for (std::size_t i = 0; i < prev_corners_.size(); ++i) {
                const cv::Point2f q = cur_pts_[i];
                if (!status_[i] || q.x < 0 || q.y < 0 || q.x > w - 1 || q.y > h - 1) continue;
                src_.push_back(prev_corners_[i]);
                dst_.push_back(q);
            }
            e.corners = static_cast<int>(prev_corners_.size());
            e.tracked = static_cast<int>(src_.size());
            e.track_ms = ms_since(t0);
            t0 = std::chrono::steady_clock::now();
            estimate(e, distance_m, level_roll, level_pitch);
            e.homography_ms = ms_since(t0);
        } else {
            // A previous frame without corners (textureless, dark) is no estimate, not a start.
            e.status = have_prev_ ? CameraStatus::TooFewPoints : CameraStatus::First;
        }

        // The thesis extracts corners in every frame and tracks them into the next.
        const auto td = std::chrono::steady_clock::now();
        cv::goodFeaturesToTrack(grey_, prev_corners_, p_.max_corners, p_.quality_level,
                                p_.min_corner_distance_px, cv::noArray(), p_.block_size);
        e.track_ms += ms_since(td);
        std::swap(prev_grey_, grey_);
        prev_roll_ = level_roll;
        prev_pitch_ = level_pitch;
        nav_roll_ = roll_deg;
        nav_pitch_ = pitch_deg;
        have_prev_ = true;
        return e;
    }

    // The last sample's translation was not used (rotation-gated, spike-zeroed): level its frame
    // by the navdata again in the next sample. The image tilt's levelling telescopes along the
    // path only over samples whose translation counts (see correct_tilt); a correction carried
    // out of a skipped sample would make the next one pay for the levelling's catch-up with the
    // navdata, which under a constant navdata bias and a yaw back and forth adds up every swing.
    void level_last_frame_by_navdata() {
        prev_roll_ = nav_roll_;
        prev_pitch_ = nav_pitch_;
    }

private:
    // Raw pixels -> the homography's pixel space (undistorted, optionally levelled, centred).
    void prepare(std::vector<cv::Point2f>& pts, double roll_deg, double pitch_deg) const {
        if (p_.undistort && calib_.has_distortion()) calib_.undistort_points(pts, pts);
        const bool level = p_.tilt_compensation && finite(roll_deg) && finite(pitch_deg);
        // The camera's rays as a level camera at the same place would see them.
        const geom::Mat3 r =
            level ? geom::camera_rotation(mount_, geom::level_from_body_matrix(roll_deg, pitch_deg))
                  : geom::Mat3::Identity();
        const double ox = p_.centre_on_principal_point ? calib_.cx : 0.0;
        const double oy = p_.centre_on_principal_point ? calib_.cy : 0.0;
        for (cv::Point2f& q : pts) {
            double x = static_cast<double>(q.x), y = static_cast<double>(q.y);
            if (level) {
                const geom::Vec3 ray =
                    r * geom::Vec3((x - calib_.cx) / calib_.fx, (y - calib_.cy) / calib_.fy, 1.0);
                x = ray.x() / ray.z() * calib_.fx + calib_.cx;
                y = ray.y() / ray.z() * calib_.fy + calib_.cy;
            }
            q = {static_cast<float>(x - ox), static_cast<float>(y - oy)};
        }
    }

    // roll_deg / pitch_deg: the navdata's for this frame on entry; on return the attitude its
    // points were levelled with (the image tilt may correct it, see correct_tilt).
    void estimate(CameraEstimate& e, double distance_m, double& roll_deg, double& pitch_deg) {
        if (e.tracked < std::max(4, p_.min_inliers)) {
            e.status = CameraStatus::TooFewPoints;
            return;
        }
        prepare(src_, prev_roll_, prev_pitch_);
        prepare(dst_, roll_deg, pitch_deg);
        const cv::Mat h =
            cv::findHomography(src_, dst_, cv::RANSAC, p_.ransac_threshold_px, mask_, 2000, 0.995);
        if (h.empty()) {
            e.status = CameraStatus::NoHomography;
            return;
        }
        e.inliers = cv::countNonZero(mask_);
        if (e.inliers < p_.min_inliers) {
            e.status = CameraStatus::TooFewInliers;
            return;
        }
        if (!finite(distance_m) || distance_m <= 0) {
            e.status = CameraStatus::NoDistance;
            return;
        }
        e.h_px = cv::Matx33d(h);
        correct_tilt(e, roll_deg, pitch_deg);
        // Without centring the homography is about the pixel origin (the thesis); the mapping to
        // metres is the same, the translation then also carries c - R c.
        e.motion = body_motion_from_homography(e.h_px, calib_.fx, calib_.fy, distance_m, mount_);
        e.status = CameraStatus::Ok;
    }

    // Tilt from the images. Over a planar floor the points map by H = R (I + t n^T / d), n the
    // floor's normal: once the points are levelled (by an attitude) n is the optical axis and
    // I + t n^T / d has no projective part, so H's third row is R's: the tilt change the
    // levelling missed (-h31 = its y rotation, h32 its x rotation, in normalised coordinates).
    // It is taken off the destination side, H' = R^T H, which also removes the translation it
    // would read (d x angle: 2 mm per 0.1 degree at 1.2 m), fused with the navdata's change by
    // their standard errors (w = the image's share).
    //
    // The current frame's levelling attitude moves by what was taken off, and the next sample
    // levels this frame with that corrected attitude, not the navdata's: a complementary filter
    // (L_k = nav_k - w x seen_k; the images' tilt changes at high frequency, the navdata's
    // attitude at low frequency). The levelling error then enters the translation only through
    // its change from one frame to the next, which telescopes over the flight: a small
    // systematic error of the projective part (about 0.004 degree per sample on the generated
    // flights) shifts the levelling by a constant instead of drifting the path, and the
    // navdata's noise reaches the translation attenuated by 1 - w. Without levelling (no
    // navdata attitude) the whole measured change is taken off per sample, as before.
    void correct_tilt(CameraEstimate& e, double& roll_deg, double& pitch_deg) const {
        if (!p_.image_tilt || !p_.centre_on_principal_point) return;
        const double h33 = e.h_px(2, 2);
        if (!finite(h33) || h33 == 0.0) return;
        const double dy = -calib_.fx * e.h_px(2, 0) / h33, dx = calib_.fy * e.h_px(2, 1) / h33;
        const bool levelled = p_.tilt_compensation && finite(roll_deg) && finite(pitch_deg) &&
                              finite(prev_roll_) && finite(prev_pitch_);
        const double vi = std::pow(p_.image_tilt_sigma_deg, 2);
        const double vn = std::pow(p_.nav_tilt_sigma_deg, 2);
        const double w = levelled ? vn / (vn + vi) : 1.0;
        const geom::Vec3 seen(dx, dy, 0);                              // camera axes, radians
        if (seen.norm() > p_.image_tilt_max_deg * kRadPerDeg) return;  // not a floor
        const geom::Vec3 d = w * seen;
        const geom::Mat3 r = geom::rotation_from_vector(d);
        const geom::Mat3 k0 = focal_scale(calib_.fx, calib_.fy);
        e.h_px = geom::to_cv(k0 * r.transpose() * k0.inverse() * geom::from_cv(e.h_px));
        e.tilt_correction_deg = {d.x() / kRadPerDeg, d.y() / kRadPerDeg};
        if (levelled) {
            // d in body axes: its x and y parts are the roll and pitch the levelling missed.
            const geom::Vec3 missed = geom::body_from_camera(mount_) * d;
            roll_deg -= missed.x() / kRadPerDeg;
            pitch_deg -= missed.y() / kRadPerDeg;
        }
    }

    CameraCalibration calib_;
    CameraMount mount_;
    const OdometryParams& p_;
    bool have_prev_ = false;
    double prev_roll_ = kUnknown, prev_pitch_ = kUnknown;  // the last frame's levelling
    double nav_roll_ = kUnknown, nav_pitch_ = kUnknown;    // ... and its navdata attitude
    cv::Mat grey_, prev_grey_, mask_;
    std::vector<cv::Point2f> prev_corners_, cur_pts_, src_, dst_;
    std::vector<std::uint8_t> status_;
    std::vector<float> err_;
};

}  // namespace

struct VisualOdometry::Impl {
    OdometryParams params;
    CameraOdometry bottom;
    std::optional<CameraOdometry> top;
    OdometryFilter filter;
    TrajectoryIntegrator integrator;
    PlanarPose start;
    PlanarPose nav_pose;
    OdometrySample last;
    std::vector<PlanarPose> path, nav_path;
    std::int64_t index = 0;
    double prev_yaw = kUnknown, nav_yaw0 = kUnknown, prev_vx = kUnknown, prev_vy = kUnknown;
    std::int64_t prev_t_ns = 0;
    bool nav_valid = false;

    Impl(const CameraCalibration& b, std::optional<CameraCalibration> t, const OdometryParams& p)
        : params(p), bottom(b, CameraMount::Bottom, params), filter(p.filter()) {
        if (t) top.emplace(*t, CameraMount::Top, params);
    }
};

VisualOdometry::VisualOdometry(const CameraCalibration& bottom,
                               std::optional<CameraCalibration> top, const OdometryParams& params)
    : impl_(std::make_unique<Impl>(bottom, std::move(top), params)) {
    reset();
}
VisualOdometry::~VisualOdometry() = default;
VisualOdometry::VisualOdometry(VisualOdometry&&) noexcept = default;
VisualOdometry& VisualOdometry::operator=(VisualOdometry&&) noexcept = default;

void VisualOdometry::reset(PlanarPose start) {
    Impl& m = *impl_;
    m.bottom.reset();
    if (m.top) m.top->reset();
    m.filter.reset();
    m.integrator.reset(start);
    m.start = start;
    m.nav_pose = start;
    m.path.clear();
    m.nav_path.clear();
    m.index = 0;
    m.prev_yaw = m.nav_yaw0 = m.prev_vx = m.prev_vy = kUnknown;
    m.prev_t_ns = 0;
    m.nav_valid = false;
    m.last = {};
    m.last.pose = m.last.nav_pose = start;
}

const OdometrySample& VisualOdometry::update(const OdometryInput& in) {
    Impl& m = *impl_;
    const auto t0 = std::chrono::steady_clock::now();
    OdometrySample& s = m.last;
    s = {};
    s.index = m.index;
    s.t_ns = in.t_ns;
    s.bottom = m.bottom.process(in.bottom, in.bottom_distance_m, in.roll_deg, in.pitch_deg);
    if (m.top) s.top = m.top->process(in.top, in.top_distance_m, in.roll_deg, in.pitch_deg);

    const bool b_ok = s.bottom.ok(), t_ok = m.top && s.top.ok();
    s.valid = b_ok || t_ok;
    if (b_ok && t_ok)
        s.raw = combine_motions(s.bottom.motion, s.top.motion);
    else if (b_ok)
        s.raw = s.bottom.motion;
    else if (t_ok)
        s.raw = s.top.motion;
    s.yaw_visual_deg = s.raw.yaw_deg;

    if (finite(in.yaw_deg) && finite(m.prev_yaw) && m.index > 0)
        s.yaw_navdata_deg = wrap_deg(in.yaw_deg - m.prev_yaw);

    double yaw = s.yaw_visual_deg;
    const bool nav = finite(s.yaw_navdata_deg);
    if (m.params.yaw_source == YawSource::Navdata && nav)
        yaw = s.yaw_navdata_deg;
    else if (m.params.yaw_source == YawSource::Fused && nav)
        yaw = s.valid ? m.params.yaw_fusion_weight * s.yaw_navdata_deg +
                            (1 - m.params.yaw_fusion_weight) * s.yaw_visual_deg
                      : s.yaw_navdata_deg;
    if (m.index > 0) {
        s.out = m.filter.apply(s.raw.forward_m, s.raw.right_m, yaw);
        s.pose = m.integrator.add(s.out.forward_m, s.out.right_m, s.out.yaw_deg);
        if (s.out.rotation_gated || s.out.spike_zeroed) {
            m.bottom.level_last_frame_by_navdata();
            if (m.top) m.top->level_last_frame_by_navdata();
        }
    } else {
        s.pose = m.integrator.pose();
    }

    // Navdata path: body velocities (trapezoid over the interval) turned by the navdata heading.
    if (finite(in.yaw_deg) && !finite(m.nav_yaw0)) m.nav_yaw0 = in.yaw_deg;
    if (m.index > 0 && finite(in.vx_mps) && finite(in.vy_mps) && finite(in.yaw_deg)) {
        const double dt = static_cast<double>(in.t_ns - m.prev_t_ns) * 1e-9;
        const double vx = finite(m.prev_vx) ? (m.prev_vx + in.vx_mps) / 2 : in.vx_mps;
        const double vy = finite(m.prev_vy) ? (m.prev_vy + in.vy_mps) / 2 : in.vy_mps;
        const double head = m.start.yaw_deg + wrap_deg(in.yaw_deg - m.nav_yaw0);
        const geom::Vec2 v_world = geom::world_from_heading(head) * geom::Vec2(vx, vy);
        m.nav_pose.x_m += v_world.x() * dt;
        m.nav_pose.y_m += v_world.y() * dt;
        m.nav_pose.yaw_deg = head;
        m.nav_valid = true;
    }
    s.nav_path_valid = m.nav_valid;
    s.nav_pose = m.nav_pose;
    m.prev_yaw = in.yaw_deg;
    m.prev_vx = in.vx_mps;
    m.prev_vy = in.vy_mps;
    m.prev_t_ns = in.t_ns;
    m.path.push_back(s.pose);
    m.nav_path.push_back(s.nav_pose);
    ++m.index;
    s.total_ms = ms_since(t0);
    return s;
}

const OdometrySample& VisualOdometry::last() const {
    return impl_->last;
}
const std::vector<PlanarPose>& VisualOdometry::path() const {
    return impl_->path;
}
const std::vector<PlanarPose>& VisualOdometry::nav_path() const {
    return impl_->nav_path;
}
const OdometryParams& VisualOdometry::params() const {
    return impl_->params;
}
bool VisualOdometry::two_cameras() const {
    return impl_->top.has_value();
}

// ---- Evaluation -----------------------------------------------------------------------------

ErrorStats error_stats(std::span<const double> e) {
    ErrorStats s;
    double sum = 0;
    for (double v : e) {
        if (!finite(v)) continue;
        s.min = s.n == 0 ? v : std::min(s.min, v);
        s.max = s.n == 0 ? v : std::max(s.max, v);
        sum += v;
        ++s.n;
    }
    if (s.n > 0) s.mean = sum / s.n;
    return s;
}

std::vector<SampleTruth> truth_from_poses(std::span<const PlanarPose> poses) {
    std::vector<SampleTruth> out(poses.size());
    for (std::size_t i = 1; i < poses.size(); ++i) {
        const geom::Vec2 d_world(poses[i].x_m - poses[i - 1].x_m, poses[i].y_m - poses[i - 1].y_m);
        const geom::Vec2 d_body = geom::world_from_heading(poses[i].yaw_deg).inverse() * d_world;
        out[i] = {d_body.x(), d_body.y(), wrap_deg(poses[i].yaw_deg - poses[i - 1].yaw_deg)};
    }
    return out;
}

OdometryErrors evaluate_odometry(std::span<const OdometrySample> samples,
                                 std::span<const PlanarPose> truth) {
    OdometryErrors r;
    const std::size_t n = std::min(samples.size(), truth.size());
    if (n == 0) return r;
    const std::vector<SampleTruth> gt = truth_from_poses(truth.first(n));
    bool any_nav = false;
    for (std::size_t i = 1; i < n; ++i) {
        const OdometrySample& s = samples[i];
        r.x_abs_m.push_back(std::abs(s.out.forward_m - gt[i].forward_m));
        r.y_abs_m.push_back(std::abs(s.out.right_m - gt[i].right_m));
        r.yaw_abs_deg.push_back(std::abs(s.out.yaw_deg - gt[i].yaw_deg));
        const double nav = std::abs(s.yaw_navdata_deg - gt[i].yaw_deg);
        r.yaw_nav_abs_deg.push_back(nav);
        any_nav = any_nav || finite(nav);
        r.distance_travelled_m +=
            std::hypot(truth[i].x_m - truth[i - 1].x_m, truth[i].y_m - truth[i - 1].y_m);
        r.max_path_error_m = std::max(
            r.max_path_error_m, std::hypot(s.pose.x_m - truth[i].x_m, s.pose.y_m - truth[i].y_m));
    }
    if (!any_nav) r.yaw_nav_abs_deg.clear();
    r.x = error_stats(r.x_abs_m);
    r.y = error_stats(r.y_abs_m);
    r.yaw = error_stats(r.yaw_abs_deg);
    r.yaw_nav = error_stats(r.yaw_nav_abs_deg);
    const OdometrySample& e = samples[n - 1];
    const PlanarPose& g = truth[n - 1];
    r.end_error_m = std::hypot(e.pose.x_m - g.x_m, e.pose.y_m - g.y_m);
    r.end_error_pct =
        r.distance_travelled_m > 0 ? 100.0 * r.end_error_m / r.distance_travelled_m : kUnknown;
    r.end_yaw_error_deg = wrap_deg(e.pose.yaw_deg - g.yaw_deg);
    if (e.nav_path_valid)
        r.nav_end_error_m = std::hypot(e.nav_pose.x_m - g.x_m, e.nav_pose.y_m - g.y_m);
    return r;
}

}  // namespace gs::vision
