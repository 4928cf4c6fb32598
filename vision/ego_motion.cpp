#include "vision/ego_motion.hpp"

#include "vision/common.hpp"
#include "vision/fit.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace gs::vision {

namespace {

// Robust weights on a residual u in noise units: Huber while the estimate settles, then Cauchy
// (redescending: a moving object's points stop pulling once they stand out).
double huber_weight(double u, double k) {
    const double a = std::abs(u);
    return a <= k ? 1.0 : k / a;
}
double cauchy_weight(double u, double k) {
    const double v = u / k;
    return 1.0 / (1.0 + v * v);
}

constexpr double kMinRay = 0.02;  // normalised: rays shorter than this (~11 px) are ill-defined

}  // namespace

double EgoMotionEstimator::rotation_cost(const cv::Vec3d& w, double sigma_n) const {
    double c = 0;
    for (const Pt& q : pts_) {
        const double ex = q.rx - (q.j[0][0] * w[0] + q.j[0][1] * w[1] + q.j[0][2] * w[2]);
        const double ey = q.ry - (q.j[1][0] * w[0] + q.j[1][1] * w[1] + q.j[1][2] * w[2]);
        const double u2 = (ex * ex + ey * ey) * q.s * q.s / (sigma_n * sigma_n * 4.0);
        c += std::log1p(u2);
    }
    return c;
}

// Robust rotation-only fit (every point: two equations J w = r) from `start`; returns the median
// residual (normalised units). Weights left in wt_.
double EgoMotionEstimator::fit_rotation_only(const cv::Vec3d& start, cv::Vec3d& w, double sigma_n) {
    const std::size_t n = pts_.size();
    w = start;
    wt_.assign(n, 1.0);
    res_.resize(n);
    for (int it = 0; it < 6; ++it) {
        for (std::size_t i = 0; i < n; ++i) {
            const Pt& q = pts_[i];
            const double ex = q.rx - (q.j[0][0] * w[0] + q.j[0][1] * w[1] + q.j[0][2] * w[2]);
            const double ey = q.ry - (q.j[1][0] * w[0] + q.j[1][1] * w[1] + q.j[1][2] * w[2]);
            res_[i] = std::sqrt(ex * ex + ey * ey);
            const double u = res_[i] * q.s / sigma_n;
            wt_[i] = (it < 3 ? huber_weight(u, 2.0) : cauchy_weight(u, 2.0)) * q.s * q.s;
        }
        cv::Matx33d a = cv::Matx33d::zeros();
        cv::Vec3d b(0, 0, 0);
        for (std::size_t i = 0; i < n; ++i) {
            const Pt& q = pts_[i];
            for (int r = 0; r < 2; ++r) {
                const cv::Vec3d jr(q.j[r][0], q.j[r][1], q.j[r][2]);
                a += wt_[i] * (jr * jr.t());
                b += wt_[i] * (r == 0 ? q.rx : q.ry) * jr;
            }
        }
        cv::Vec3d sol;
        if (!cv::solve(a, b, sol, cv::DECOMP_CHOLESKY)) break;
        w = sol;
    }
    for (std::size_t i = 0; i < n; ++i) {
        const Pt& q = pts_[i];
        const double ex = q.rx - (q.j[0][0] * w[0] + q.j[0][1] * w[1] + q.j[0][2] * w[2]);
        const double ey = q.ry - (q.j[1][0] * w[0] + q.j[1][1] * w[1] + q.j[1][2] * w[2]);
        res_[i] = std::sqrt(ex * ex + ey * ey);
    }
    // The median of a scratch copy (res_ keeps the per-point residuals).
    scratch_.assign(res_.begin(), res_.end());
    return median_inplace(scratch_);
}

// Rotation w (on top of the prior) and translation direction t, alternating. Returns false when
// the system is degenerate. info_t: the information matrix of t; info_w, b_w:
// the normal equations of w without its prior (w_images = info_w^-1 b_w).
bool EgoMotionEstimator::fit_translation(const EgoPrior& prior, bool fix_w, double sigma_n,
                                         const EgoMotionParams& p, cv::Vec3d& w, cv::Vec3d& t,
                                         cv::Matx33d& info_t, cv::Matx33d& info_w, cv::Vec3d& b_w) {
    const std::size_t n = pts_.size();
    // The velocity's direction only starts the search: the images' FOE is their own, and the
    // caller fuses the two knowing both errors.
    const bool t_prior = !std::isnan(prior.translation[0]);
    if (!fix_w) {
        wt_.assign(n, 1.0);
        res_.assign(n, 0.0);
    }
    bool have_t = t_prior || fix_w;
    if (t_prior && !fix_w) t = prior.translation;
    const int iters = std::max(2, p.iterations);
    // The flow less the rotation's, per point: computed again only when w changes (a buffer
    // kept per thread, so no frame allocates once it has grown).
    thread_local std::vector<cv::Vec2d> derot;
    derot.resize(n);
    const auto derotate = [&] {
        for (std::size_t i = 0; i < n; ++i) {
            const Pt& q = pts_[i];
            derot[i] = {q.rx - (q.j[0][0] * w[0] + q.j[0][1] * w[1] + q.j[0][2] * w[2]),
                        q.ry - (q.j[1][0] * w[0] + q.j[1][1] * w[1] + q.j[1][2] * w[2])};
        }
    };
    derotate();
    for (int it = 0; it < iters; ++it) {
        // t given w: the derotated flow must be parallel to the ray from the FOE. Each point's
        // residual a . t is divided by its standard deviation (sigma times the ray's length L,
        // as a = B g with g's noise isotropic and |B^T t| = L, L taken from the last iterate).
        cv::Matx33d m = cv::Matx33d::zeros();
        for (std::size_t i = 0; i < n; ++i) {
            const Pt& q = pts_[i];
            const double gx = derot[i][0], gy = derot[i][1];
            const cv::Vec3d a(gy, -gx, gx * q.y - gy * q.x);
            double l2 = 1.0;
            if (have_t) {
                const double lx = q.x * t[2] - t[0], ly = q.y * t[2] - t[1];
                l2 = std::max(lx * lx + ly * ly, kMinRay * kMinRay);
            }
            m += (wt_[i] * q.s * q.s / (l2 * sigma_n * sigma_n)) * (a * a.t());
        }
        info_t = m;
        cv::Vec3d vals;
        cv::Matx33d vecs;
        cv::eigen(m, vals, vecs);
        if (!(vals[1] > 0)) return false;
        cv::Vec3d tn(vecs(2, 0), vecs(2, 1), vecs(2, 2));
        // Oriented so that static points flow away from the FOE (their depth is positive).
        double s = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const Pt& q = pts_[i];
            const double gx = derot[i][0], gy = derot[i][1];
            s += wt_[i] * (gx * (q.x * tn[2] - tn[0]) + gy * (q.y * tn[2] - tn[1]));
        }
        if (s < 0) tn = -tn;
        t = tn;
        have_t = true;

        // w given t: the flow across each ray is rotation.
        cv::Matx33d a = cv::Matx33d::zeros();
        cv::Vec3d b(0, 0, 0);
        for (std::size_t i = 0; i < n; ++i) {
            const Pt& q = pts_[i];
            const double lx = q.x * t[2] - t[0], ly = q.y * t[2] - t[1];
            const double l = std::max(std::sqrt(lx * lx + ly * ly), kMinRay);
            const double nx = -ly / l, ny = lx / l;
            const cv::Vec3d an(nx * q.j[0][0] + ny * q.j[1][0], nx * q.j[0][1] + ny * q.j[1][1],
                               nx * q.j[0][2] + ny * q.j[1][2]);
            const double bn = nx * q.rx + ny * q.ry;
            const double wi = wt_[i] * q.s * q.s / (sigma_n * sigma_n);
            a += wi * (an * an.t());
            b += wi * bn * an;
        }
        info_w = a;
        b_w = b;
        if (!fix_w) {
            cv::Vec3d sol;
            if (!cv::solve(a, b, sol, cv::DECOMP_SVD)) return false;
            w = sol;
            derotate();
        }

        // Residuals (noise units) and the next weights.
        for (std::size_t i = 0; i < n; ++i) {
            const Pt& q = pts_[i];
            const double gx = derot[i][0], gy = derot[i][1];
            const double lx = q.x * t[2] - t[0], ly = q.y * t[2] - t[1];
            const double l = std::max(std::sqrt(lx * lx + ly * ly), kMinRay);
            res_[i] = (-ly * gx + lx * gy) / l * q.s / sigma_n;
            wt_[i] = it < iters / 2 ? huber_weight(res_[i], p.huber_k)
                                    : cauchy_weight(res_[i], p.huber_k);
        }
    }
    return true;
}

// The images' rotation correction (w_img, covariance cov_img) against the navdata prior (no
// correction, sigma sp per axis): rejected when they disagree beyond prior_gate standard errors,
// else fused. The images' covariance is never taken as better than image_floor_deg per axis:
// a scene that barely separates a rotation from a shift of the FOE (a wall seen head-on) can
// make the fit confident and wrong, and the attitude's frame-to-frame change is good to
// ~0.1 degree. Returns the correction to apply; sets prior_rotation_used / _rejected.
cv::Vec3d EgoMotionEstimator::fuse_rotation(const EgoMotionParams& p, const cv::Matx33d& cov_img,
                                            const cv::Vec3d& w_img, double sp) {
    const double fl = p.image_floor_deg * kRadPerDeg;
    const cv::Matx33d ci = cov_img + cv::Matx33d::eye() * (fl * fl);
    m_.image_rad = w_img;
    m_.image_var = {ci(0, 0), ci(1, 1), ci(2, 2)};
    cv::Matx33d sum_inv;
    cv::invert(ci + cv::Matx33d::eye() * (sp * sp), sum_inv, cv::DECOMP_SVD);
    if ((w_img.t() * sum_inv * w_img)(0) > p.prior_gate * p.prior_gate) {
        m_.prior_rotation_rejected = true;
        return w_img;
    }
    m_.prior_rotation_used = true;
    cv::Matx33d info_img;
    cv::invert(ci, info_img, cv::DECOMP_SVD);
    cv::Vec3d fused;
    if (!cv::solve(info_img + cv::Matx33d::eye() * (1.0 / (sp * sp)), info_img * w_img, fused,
                   cv::DECOMP_SVD))
        return {0, 0, 0};
    return fused;
}

// No translation seen: the rotation alone (w_rot, fitted on every point's 2-D flow) explains the
// scene; what it does not explain moves by itself. Gates and fuses the navdata rotation.
void EgoMotionEstimator::finish_still(const EgoPrior& prior, const EgoMotionParams& p,
                                      double sigma_n, double f, const cv::Vec3d& w_rot,
                                      double med_rot) {
    const std::size_t n = pts_.size();
    const double sp = std::max(1e-6, prior.rotation_sigma_deg * kRadPerDeg);
    std::fill(outlier_.begin(), outlier_.end(), std::uint8_t{0});
    m_.translation = EgoMotion::Translation::None;
    cv::Vec3d w = w_rot;
    if (prior.rotation) {
        // Gate the prior (zero correction) against the images' estimate, then fuse.
        cv::Matx33d a = cv::Matx33d::zeros();
        cv::Vec3d b(0, 0, 0);
        for (std::size_t i = 0; i < n; ++i) {
            const Pt& q = pts_[i];
            const double wi =
                cauchy_weight(res_rot_[i] * q.s / sigma_n, 2.0) * q.s * q.s / (sigma_n * sigma_n);
            for (int r = 0; r < 2; ++r) {
                const cv::Vec3d jr(q.j[r][0], q.j[r][1], q.j[r][2]);
                a += wi * (jr * jr.t());
                b += wi * (r == 0 ? q.rx : q.ry) * jr;
            }
        }
        cv::Matx33d cov_img;
        if (cv::invert(a, cov_img, cv::DECOMP_SVD) == 0) cov_img = cv::Matx33d::eye() * 1e6;
        w = fuse_rotation(p, cov_img, w_rot, sp);
    }
    m_.correction_rad = w;
    m_.residual_px = med_rot * f;
    int out = 0;
    scratch_.clear();
    for (std::size_t i = 0; i < n; ++i) {
        const Pt& q = pts_[i];
        const double ex = q.rx - (q.j[0][0] * w[0] + q.j[0][1] * w[1] + q.j[0][2] * w[2]);
        const double ey = q.ry - (q.j[1][0] * w[0] + q.j[1][1] * w[1] + q.j[1][2] * w[2]);
        const double r = std::sqrt(ex * ex + ey * ey);
        scratch_.push_back(r);
        if (r * q.s > p.outlier_k * sigma_n) {
            outlier_[i] = 1;
            ++out;
        }
    }
    m_.translation_px = median_inplace(scratch_) * f;
    m_.outliers = out;
}

// Information matrix (noise units) of the tangential residuals in t's two tangent directions
// (e1, e2, returned) and the rotation w, at (t, w), with the current robust weights.
cv::Matx<double, 5, 5> EgoMotionEstimator::joint_information(const cv::Vec3d& t, const cv::Vec3d& w,
                                                             double sigma_n, cv::Vec3d& e1,
                                                             cv::Vec3d& e2) const {
    e1 = t.cross(std::abs(t[0]) < 0.9 ? cv::Vec3d(1, 0, 0) : cv::Vec3d(0, 1, 0));
    e1 *= 1.0 / cv::norm(e1);
    e2 = t.cross(e1);
    cv::Matx<double, 5, 5> info = cv::Matx<double, 5, 5>::zeros();
    constexpr double kEps = 1e-5;
    for (std::size_t i = 0; i < pts_.size(); ++i) {
        const Pt& q = pts_[i];
        const double gx = q.rx - (q.j[0][0] * w[0] + q.j[0][1] * w[1] + q.j[0][2] * w[2]);
        const double gy = q.ry - (q.j[1][0] * w[0] + q.j[1][1] * w[1] + q.j[1][2] * w[2]);
        auto tangential = [&](const cv::Vec3d& tt) {
            const double lx = q.x * tt[2] - tt[0], ly = q.y * tt[2] - tt[1];
            const double l = std::max(std::sqrt(lx * lx + ly * ly), kMinRay);
            return (-ly * gx + lx * gy) / l;
        };
        const double r0 = tangential(t);
        cv::Vec<double, 5> g;
        g[0] = (tangential(t + kEps * e1) - r0) / kEps;
        g[1] = (tangential(t + kEps * e2) - r0) / kEps;
        const double lx = q.x * t[2] - t[0], ly = q.y * t[2] - t[1];
        const double l = std::max(std::sqrt(lx * lx + ly * ly), kMinRay);
        const double nx = -ly / l, ny = lx / l;
        for (int k = 0; k < 3; ++k) g[2 + k] = -(nx * q.j[0][k] + ny * q.j[1][k]);
        info += (wt_[i] * q.s * q.s / (sigma_n * sigma_n)) * (g * g.t());
    }
    return info;
}

// The estimate's description for a rotation w and direction t: FOE and its error (from the
// joint information `info` in t's tangent directions e1, e2 and w), the velocity prior's
// check, and which points do not follow (their flow across the ray, or toward the FOE: a static
// point cannot recede while the camera moves toward it).
void EgoMotionEstimator::describe_translation(const CameraCalibration& calib, const cv::Vec3d& w,
                                              const cv::Vec3d& t,
                                              const cv::Matx<double, 5, 5>& info,
                                              const cv::Vec3d& e1, const cv::Vec3d& e2) {
    const EgoPrior& prior = last_.prior;
    const EgoMotionParams& p = last_.p;
    const double sigma_n = last_.sigma_n, f = last_.f;
    const std::size_t n = pts_.size();
    m_.correction_rad = w;
    m_.translation = EgoMotion::Translation::Known;
    m_.direction = t;
    scratch_.clear();
    for (double r : res_) scratch_.push_back(std::abs(r));
    m_.residual_px = median_inplace(scratch_) * p.noise_px;
    // Uncertainty of t: the joint information of the five parameters (t's two tangent
    // directions, w) marginalised to t.
    cv::Matx33d cov_t = cv::Matx33d::eye() * 1e6;
    {
        cv::Matx<double, 5, 5> cov;
        if (cv::invert(info, cov, cv::DECOMP_SVD) != 0) {
            const cv::Matx<double, 3, 2> e(e1[0], e2[0], e1[1], e2[1], e1[2], e2[2]);
            const cv::Matx22d c2(cov(0, 0), cov(0, 1), cov(1, 0), cov(1, 1));
            cov_t = e * c2 * e.t();
            if (!std::isnan(prior.translation[0])) {
                // The velocity's direction against the images', in the tangent plane.
                const cv::Vec3d d = prior.translation - t;
                const cv::Vec2d dd(d.dot(e1), d.dot(e2));
                const double st2 = prior.translation_sigma_rad * prior.translation_sigma_rad;
                const cv::Matx22d sum = c2 + cv::Matx22d::eye() * st2;
                cv::Matx22d inv;
                if (cv::invert(sum, inv, cv::DECOMP_SVD) != 0 &&
                    (dd.t() * inv * dd)(0) > p.prior_gate * p.prior_gate)
                    m_.prior_translation_rejected = true;
            }
        }
    }
    if (t[2] > 0.05) {
        const cv::Point2d foe = calib.project(t);
        m_.foe = {static_cast<float>(foe.x), static_cast<float>(foe.y)};
        const double iz = 1.0 / t[2];
        const cv::Matx23d d(calib.fx * iz, 0, -calib.fx * t[0] * iz * iz, 0, calib.fy * iz,
                            -calib.fy * t[1] * iz * iz);
        const cv::Matx22d ce = d * cov_t * d.t();
        const double tr = ce(0, 0) + ce(1, 1);
        const double det = ce(0, 0) * ce(1, 1) - ce(0, 1) * ce(1, 0);
        const double lmax = 0.5 * tr + std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
        m_.foe_sigma_px = std::sqrt(lmax);
    }
    // Outliers: flow across the ray, or toward the FOE (a static point cannot recede while
    // the camera moves toward it).
    int out = 0;
    scratch_.clear();
    for (std::size_t i = 0; i < n; ++i) {
        const Pt& q = pts_[i];
        const double gx = q.rx - (q.j[0][0] * w[0] + q.j[0][1] * w[1] + q.j[0][2] * w[2]);
        const double gy = q.ry - (q.j[1][0] * w[0] + q.j[1][1] * w[1] + q.j[1][2] * w[2]);
        scratch_.push_back(std::sqrt(gx * gx + gy * gy));
        const double lx = q.x * t[2] - t[0], ly = q.y * t[2] - t[1];
        const double l = std::max(std::sqrt(lx * lx + ly * ly), kMinRay);
        const double radial = (gx * lx + gy * ly) / l * q.s / sigma_n;
        if (std::abs(res_[i]) > p.outlier_k || radial < -p.outlier_k) {
            outlier_[i] = 1;
            ++out;
        }
    }
    m_.translation_px = median_inplace(scratch_) * f;
    m_.outliers = out;
}

const EgoMotion& EgoMotionEstimator::refine(const CameraCalibration& calib,
                                            const cv::Vec3d& w_applied) {
    if (!m_.valid || m_.translation != EgoMotion::Translation::Known) {
        if (m_.valid) m_.correction_rad = w_applied;
        return m_;
    }
    cv::Vec3d w = w_applied, t = m_.direction;
    cv::Matx33d info_t, info_w;
    cv::Vec3d b_w;
    if (!fit_translation(last_.prior, true, last_.sigma_n, last_.p, w, t, info_t, info_w, b_w))
        return m_;
    cv::Vec3d e1, e2;
    cv::Matx<double, 5, 5> info = joint_information(t, w, last_.sigma_n, e1, e2) * (1.0 / last_.s2);
    if (m_.prior_rotation_used) {
        const double sp = std::max(1e-6, last_.prior.rotation_sigma_deg * kRadPerDeg);
        for (int k = 2; k < 5; ++k) info(k, k) += 1.0 / (sp * sp);
    }
    std::fill(outlier_.begin(), outlier_.end(), std::uint8_t{0});
    describe_translation(calib, w, t, info, e1, e2);
    return m_;
}

// Translating: rotation and translation direction together. False when that does not explain
// the scene better than a still camera with moving objects (the caller then takes that).
bool EgoMotionEstimator::finish_translating(const CameraCalibration& calib, const EgoPrior& prior,
                                            const EgoMotionParams& p, double sigma_n, double f,
                                            const cv::Vec3d& w_rot, int rotation_outliers,
                                            bool was_translating) {
    const double sp = std::max(1e-6, prior.rotation_sigma_deg * kRadPerDeg);
    std::fill(outlier_.begin(), outlier_.end(), std::uint8_t{0});
    // 1. The images alone, started from no correction (the navdata's rotation, or none) and
    // from the rotation-only estimate; the better fit is kept.
    cv::Vec3d w_img, t_img;
    cv::Matx33d info_t, info_w;
    cv::Vec3d b_w;
    bool ok = false;
    double best_c = 0;
    for (const cv::Vec3d& start : {cv::Vec3d(0, 0, 0), w_rot}) {
        cv::Vec3d w = start, t(0, 0, 1);
        cv::Matx33d it_, iw_;
        cv::Vec3d bw_;
        if (!fit_translation(prior, false, sigma_n, p, w, t, it_, iw_, bw_)) continue;
        double c = 0;
        for (double r : res_) c += std::log1p(r * r / (p.huber_k * p.huber_k));
        if (!ok || c < best_c) {
            ok = true;
            best_c = c;
            w_img = w;
            t_img = t;
        }
    }
    if (!ok) return false;
    cv::Vec3d w = w_img, t = t_img;
    fit_translation(prior, false, sigma_n, p, w, t, info_t, info_w, b_w);  // res_ for this one
    // Residual scale (noise units): 1 when the noise model holds; larger widens the errors.
    scratch_.clear();
    for (double r : res_) scratch_.push_back(r * r);
    const double s2 = std::max(1.0, median_inplace(scratch_) / 0.455);
    // 2. With a navdata rotation: what the images know of the rotation once the translation's
    // direction is left free (a small yaw and a shift of the FOE explain similar flows, so
    // that direction is weak), gated against the prior and fused with it; then the direction
    // again for that rotation.
    cv::Vec3d e1, e2;
    cv::Matx<double, 5, 5> info = joint_information(t, w, sigma_n, e1, e2) * (1.0 / s2);
    if (prior.rotation) {
        const cv::Matx22d htt(info(0, 0), info(0, 1), info(1, 0), info(1, 1));
        cv::Matx22d htt_inv;
        cv::Matx33d mw;
        if (cv::invert(htt, htt_inv, cv::DECOMP_SVD) != 0) {
            cv::Matx<double, 3, 2> hwt;
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 2; ++c) hwt(r, c) = info(2 + r, c);
            cv::Matx33d hww;
            for (int r = 0; r < 3; ++r)
                for (int c = 0; c < 3; ++c) hww(r, c) = info(2 + r, 2 + c);
            mw = hww - hwt * htt_inv * hwt.t();
        } else {
            mw = cv::Matx33d::zeros();
        }
        cv::Matx33d cov_img;
        if (cv::invert(mw, cov_img, cv::DECOMP_SVD) == 0) cov_img = cv::Matx33d::eye() * 1e6;
        w = fuse_rotation(p, cov_img, w_img, sp);
        if (m_.prior_rotation_used) {
            fit_translation(prior, true, sigma_n, p, w, t, info_t, info_w, b_w);
            info = joint_information(t, w, sigma_n, e1, e2) * (1.0 / s2);
            for (int k = 2; k < 5; ++k) info(k, k) += 1.0 / (sp * sp);
        }
    }
    last_ = {prior, p, sigma_n, f, s2};
    describe_translation(calib, w, t, info, e1, e2);
    // A translation that explains no more than a still camera would (half the points it could
    // not explain, at least), or whose FOE cannot be placed, is not taken without navdata: a
    // hand waved in front of a camera on a table is not the camera flying.
    const bool prior_t = !std::isnan(prior.translation[0]);
    const bool reliable = m_.direction[2] > 0.2 && m_.foe_sigma_px <= p.reliable_foe_sigma_px;
    return prior_t || was_translating || (2 * m_.outliers <= rotation_outliers && reliable);
}

const EgoMotion& EgoMotionEstimator::estimate(const CameraCalibration& calib,
                                              std::span<const cv::Point2f> pred,
                                              std::span<const cv::Point2f> cur,
                                              const EgoPrior& prior, const EgoMotionParams& p,
                                              std::span<const float> quality) {
    // A camera that has been translating for a few frames does not stop at once: then only
    // the translation model failing outright makes it still.
    known_run_ = m_.translation == EgoMotion::Translation::Known ? known_run_ + 1 : 0;
    const bool was_translating = known_run_ >= 3;
    m_ = {};
    const std::size_t n = std::min(pred.size(), cur.size());
    outlier_.assign(n, 0);
    m_.points = static_cast<int>(n);
    if (static_cast<int>(n) < std::max(4, p.min_points) || !calib.valid()) return m_;
    const double f = 0.5 * (calib.fx + calib.fy);
    const double sigma_n = std::max(1e-3, p.noise_px) / f;
    pts_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        Pt& q = pts_[i];
        q.x = (static_cast<double>(pred[i].x) - calib.cx) / calib.fx;
        q.y = (static_cast<double>(pred[i].y) - calib.cy) / calib.fy;
        q.rx = static_cast<double>(cur[i].x - pred[i].x) / calib.fx;
        q.ry = static_cast<double>(cur[i].y - pred[i].y) / calib.fy;
        q.s = 1.0;
        // d(x, y) / d(w) for p' = (I + [w]x) p (cv::Rodrigues' sign, as K R K^-1 moves points).
        q.j[0][0] = -q.x * q.y;
        q.j[0][1] = 1 + q.x * q.x;
        q.j[0][2] = -q.y;
        q.j[1][0] = -(1 + q.y * q.y);
        q.j[1][1] = q.x * q.y;
        q.j[1][2] = q.x;
    }
    if (quality.size() >= n) {
        // Relative to the median point: a point as well conditioned as most counts fully, one
        // whose gradient matrix is ten times weaker as if its noise were three times larger.
        scratch_.assign(quality.begin(), quality.begin() + static_cast<std::ptrdiff_t>(n));
        const double med = median_inplace(scratch_);
        if (med > 0)
            for (std::size_t i = 0; i < n; ++i)
                pts_[i].s = std::sqrt(std::clamp(static_cast<double>(quality[i]) / med, 0.05, 1.0));
    }

    // 1. Rotation alone, started from the best of a few deterministic candidates (none, and the
    // least-squares rotation of each sixth of the image), so that a large moving object cannot
    // capture the start.
    std::array<cv::Vec3d, 7> cand{};
    std::size_t nc = 1;
    for (int cell = 0; cell < 6; ++cell) {
        cv::Matx33d a = cv::Matx33d::zeros();
        cv::Vec3d b(0, 0, 0);
        int cnt = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const Pt& q = pts_[i];
            const double u = static_cast<double>(pred[i].x) / calib.width;
            const double v = static_cast<double>(pred[i].y) / calib.height;
            const int c = std::clamp(static_cast<int>(u * 3), 0, 2) +
                          3 * std::clamp(static_cast<int>(v * 2), 0, 1);
            if (c != cell) continue;
            ++cnt;
            for (int r = 0; r < 2; ++r) {
                const cv::Vec3d jr(q.j[r][0], q.j[r][1], q.j[r][2]);
                a += jr * jr.t();
                b += (r == 0 ? q.rx : q.ry) * jr;
            }
        }
        cv::Vec3d s;
        if (cnt >= 4 && cv::solve(a, b, s, cv::DECOMP_SVD)) cand[nc++] = s;
    }
    std::size_t best = 0;
    double best_cost = rotation_cost(cand[0], sigma_n);
    for (std::size_t k = 1; k < nc; ++k) {
        const double c = rotation_cost(cand[k], sigma_n);
        if (c < best_cost) {
            best_cost = c;
            best = k;
        }
    }
    cv::Vec3d w_rot;
    const double med_rot = fit_rotation_only(cand[best], w_rot, sigma_n);

    res_rot_.assign(res_.begin(), res_.end());
    int rotation_outliers = 0;
    for (std::size_t i = 0; i < n; ++i)
        rotation_outliers += res_rot_[i] * pts_[i].s > p.outlier_k * sigma_n;
    // Still when a rotation explains nearly every point, unless the navdata says the drone
    // moves (then the few points with translational flow are near, not moving by themselves).
    // Without navdata also when the median point barely moves, however many others do (people
    // and hands in front of a camera on a table, a hovering drone): a scene whose majority
    // moves under still_k noise units a frame approaches, if at all, with a time to contact of
    // tens of seconds, and the points that do move are judged as moving objects, by their
    // looming. Neither the few-outliers rule nor a camera that was translating overrides it.
    const bool no_prior_t = std::isnan(prior.translation[0]);
    const bool still = no_prior_t && ((!was_translating &&
                                       rotation_outliers <= std::max(3, static_cast<int>(n) / 20) &&
                                       med_rot * f <= p.translation_k * p.noise_px) ||
                                      med_rot * f <= p.still_k * p.noise_px);
    const EgoMotion before = m_;
    if (still) {
        finish_still(prior, p, sigma_n, f, w_rot, med_rot);
    } else if (!finish_translating(calib, prior, p, sigma_n, f, w_rot, rotation_outliers,
                                   was_translating)) {
        m_ = before;
        finish_still(prior, p, sigma_n, f, w_rot, med_rot);
    }
    m_.valid = cv::norm(m_.correction_rad) <= p.max_rotation_deg * kRadPerDeg;
    if (!m_.valid) m_.translation = EgoMotion::Translation::Unknown;
    return m_;
}

void NavdataRateError::reset(const RateErrorParams& p) {
    p_ = p;
    const double sb = p_.bias_sigma_dps * kRadPerDeg;
    for (Axis& a : axes_)
        a = {{0, 0}, cv::Matx22d(sb * sb, 0, 0, p_.scale_sigma * p_.scale_sigma), kUnknown};
    hist_n_ = 0;
    mismatch_ = {};
    lag_s_ = 0;
}

void NavdataRateError::measure_lag(const cv::Vec3d& image_rad, const cv::Vec3d& nav_rot,
                                   double dt) {
    std::rotate(nav_hist_.begin(), nav_hist_.begin() + 1, nav_hist_.end());
    std::rotate(img_hist_.begin(), img_hist_.begin() + 1, img_hist_.end());
    nav_hist_.back() = nav_rot;
    img_hist_.back() = nav_rot + image_rad;
    if (++hist_n_ < 4) return;
    hist_n_ = 4;
    // The images' rotation two frames back against the navdata's from one frame before it to
    // two after: a navdata late by L frames matches best L frames on.
    const double a = std::exp(-dt / p_.lag_tau_s);
    const cv::Vec3d& img = img_hist_[1];
    for (std::size_t s = 0; s < 4; ++s) {
        const cv::Vec3d d = img - nav_hist_[s];
        mismatch_[s] = a * mismatch_[s] + d.dot(d);
    }
    // The best shift, refined by a parabola through its neighbours; none unless it beats no
    // shift (index 1) clearly: noise alone raises every shift's mismatch alike.
    const auto best = static_cast<std::size_t>(
        std::min_element(mismatch_.begin(), mismatch_.end()) - mismatch_.begin());
    double shift = static_cast<double>(best) - 1.0;
    if (best > 0 && best < 3) {
        const double l = mismatch_[best - 1], m = mismatch_[best], r = mismatch_[best + 1];
        const double curv = l - 2 * m + r;
        if (curv > 0) shift += std::clamp(0.5 * (l - r) / curv, -0.5, 0.5);
    }
    // A best match at the edge of the shifts tried (the navdata two frames late, or a frame
    // early) is no lag a link has: the images misread a manoeuvre. A lag found is the link's,
    // not the frame's: kept until another shift clearly matches better (or none does best).
    if (best == 0 || best == 3) return;
    if (mismatch_[best] < (1 - p_.lag_min_gain) * mismatch_[1] || best == 1)
        lag_s_ = std::max(shift, 0.0) * dt;
}

cv::Vec3d NavdataRateError::update(const cv::Vec3d& image_rad, const cv::Vec3d& image_var,
                                   const cv::Vec3d& nav_rot, double dt) {
    if (!(dt > 0)) return {0, 0, 0};
    measure_lag(image_rad, nav_rot, dt);
    const double lag = std::min(p_.latency_sigma_s, p_.lag_k * lag_s_);
    const double a = std::exp(-dt / p_.bias_tau_s);
    const double sb = p_.bias_sigma_dps * kRadPerDeg;
    const double qs = p_.scale_walk * p_.scale_walk * dt;
    cv::Vec3d corr;
    for (int k = 0; k < 3; ++k) {
        Axis& e = axes_[static_cast<std::size_t>(k)];
        // Predict: the bias decays toward zero and its variance toward sb^2; the scale walks.
        e.x[0] *= a;
        e.p(0, 0) = a * a * e.p(0, 0) + (1 - a * a) * sb * sb;
        e.p(0, 1) *= a;
        e.p(1, 0) *= a;
        e.p(1, 1) += qs;
        // Update with this frame's measured rate error, z = b + s w + a passing latency error
        // (its variance from the change of the navdata rate since the last update).
        const double rate = nav_rot[k] / dt;
        const double lat = std::isnan(e.last_rate) ? 0.0 : lag * (rate - e.last_rate) / dt;
        e.last_rate = rate;
        const double q = lat * lat;
        const cv::Vec2d h(1, rate);
        const cv::Vec2d ph = e.p * h;
        const double s = h.dot(ph) + image_var[k] / (dt * dt) + q;
        const cv::Vec2d gain = ph * (1 / s);
        const double innovation = image_rad[k] / dt - h.dot(e.x);
        e.x += gain * innovation;
        e.p -= gain * ph.t();
        corr[k] = (h.dot(e.x) + q / s * innovation) * dt;
    }
    return corr;
}

}  // namespace gs::vision
