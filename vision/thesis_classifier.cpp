#include "vision/thesis_classifier.hpp"
#include "drone/core/unknown.hpp"

#include "vision/fit.hpp"

#include <opencv2/calib3d.hpp>

#include <algorithm>

namespace gs::vision {

const ParamTable<ThesisParams>& ThesisParams::table() {
    static const ParamTable<ThesisParams> t = [] {
        ParamTable<ThesisParams> tab;
        using P = ThesisParams;
        tab.add("centre_band_px", &P::centre_band_px, 5, 400,
                "centre region half-width around the image centre")
            .add("slope_window", &P::slope_window, 2, static_cast<double>(Trajectory::kHistory),
                 "slope over the last n points; trajectories need at least n")
            .add("edge_scale", &P::edge_scale, 0.1, 20, "slope position scale at the image edges")
            .add("centre_scale", &P::centre_scale, 0.1, 20,
                 "slope position scale at the image centre")
            .add("scale_multiplies", &P::scale_multiplies, 0, 1,
                 "1: slope * position scale (reproduces the thesis distances); 0: slope / scale")
            .add("outward_slope", &P::outward_slope, 0, 1,
                 "1: slope toward the image edge; 0: absolute slope")
            .add("cluster_distance_px", &P::cluster_distance_px, 1, 200,
                 "cluster trajectories whose end points are closer than this")
            .add("cluster_slope_diff", &P::cluster_slope_diff, 0.01, 10,
                 "... and whose scaled slopes differ by less than this")
            .add("cluster_min_size", &P::cluster_min_size, 0, 200,
                 "side unsafe when a cluster has more than this many steep trajectories")
            .add("slope_threshold", &P::slope_threshold, 0, 50,
                 "a trajectory is steep above this scaled slope (px/frame)")
            .add("homography_ransac_px", &P::homography_ransac_px, 0.1, 20,
                 "centre homography RANSAC reprojection threshold")
            .add("homography_min_points", &P::homography_min_points, 4, 500,
                 "fewest centre points for a scale sample")
            .add("filter_alpha", &P::filter_alpha, 0, 0.999, "low-pass constant for the scale")
            .add("fit_window", &P::fit_window, 3, 256,
                 "second-order fit over the last n filtered scales")
            .add("centre_slope_threshold", &P::centre_slope_threshold, 0, 1,
                 "centre unsafe when the fitted tangent slope exceeds this (per sample)")
            .add("colour_min", &P::colour_min, 0, 50, "overlay: blue at this scaled slope")
            .add("colour_max", &P::colour_max, 0, 50, "overlay: red at this scaled slope");
        describe_tracker_params(tab);  // after the classifier's own: what users tune first
        return tab;
    }();
    return t;
}

ThesisClassifier::ThesisClassifier(const CameraCalibration& calib, const ThesisParams& p)
    : TrackingClassifier(calib), p_(p) {
    s_scale_raw_ = add_series("centre.scale_raw");
    s_scale_filt_ = add_series("centre.scale_filtered");
    s_scale_fit_ = add_series("centre.scale_fitted");
    reconfigure();
}

void ThesisClassifier::on_reset() {
    filtered_.clear();
    filter_state_ = kUnknown;
}

void ThesisClassifier::classify(const FrameInput&) {
    classify_sides();
    classify_centre();
}

int ThesisClassifier::find(int i) {
    while (parent_[static_cast<std::size_t>(i)] != i) {
        auto& pi = parent_[static_cast<std::size_t>(i)];
        pi = parent_[static_cast<std::size_t>(pi)];
        i = pi;
    }
    return i;
}

void ThesisClassifier::classify_sides() {
    const auto& tracks = tracker_.tracks();
    const auto n = static_cast<std::size_t>(p_.slope_window);
    const auto w = static_cast<double>(calib_.width);
    cand_.clear();
    xs_.resize(n);
    for (std::size_t i = 0; i < tracks.size(); ++i) {
        const Trajectory& t = tracks[i];
        if (t.history_size() < n) continue;
        for (std::size_t k = 0; k < n; ++k)
            xs_[k] = static_cast<double>(t.at_back(n - 1 - k).stab.x);
        const LineFit f = fit_line_indexed(xs_);
        if (!f.ok) continue;
        const cv::Point2f pos = t.at_back(0).stab;
        const Region reg = region_of(pos.x);
        double slope = f.slope;
        if (p_.outward_slope)
            slope = reg == Region::Left ? -slope : (reg == Region::Right ? slope : std::abs(slope));
        else
            slope = std::abs(slope);
        const double s =
            position_scale(static_cast<double>(pos.x), w, p_.edge_scale, p_.centre_scale);
        const double scaled = p_.scale_multiplies ? slope * s : slope / s;
        track_score_[i] = scaled;
        if (reg != Region::Centre) cand_.push_back({i, static_cast<int>(reg), pos, scaled});
    }
    // Single-linkage clustering (union-find) within each side.
    const std::size_t m = cand_.size();
    parent_.resize(m);
    count_.assign(m, 0);
    for (std::size_t i = 0; i < m; ++i) parent_[i] = static_cast<int>(i);
    const auto d2max = static_cast<float>(p_.cluster_distance_px * p_.cluster_distance_px);
    for (std::size_t i = 0; i < m; ++i)
        for (std::size_t j = i + 1; j < m; ++j) {
            const Candidate& a = cand_[i];
            const Candidate& b = cand_[j];
            if (a.side != b.side) continue;
            const cv::Point2f d = a.pos - b.pos;
            if (d.dot(d) >= d2max) continue;
            if (std::abs(a.scaled - b.scaled) >= p_.cluster_slope_diff) continue;
            const int ra = find(static_cast<int>(i)), rb = find(static_cast<int>(j));
            if (ra != rb) parent_[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
        }
    int best[3] = {0, 0, 0};
    int support[3] = {0, 0, 0};
    for (std::size_t i = 0; i < m; ++i) {
        ++support[cand_[i].side];
        if (cand_[i].scaled > p_.slope_threshold) {
            const auto root = static_cast<std::size_t>(find(static_cast<int>(i)));
            const int c = ++count_[root];
            best[cand_[i].side] = std::max(best[cand_[i].side], c);
        }
    }
    for (int side : {0, 2}) {
        RegionDecision& d = result_.regions[static_cast<std::size_t>(side)];
        d.threshold = p_.cluster_min_size;
        d.support = support[side];
        d.score = best[side];
        d.unsafe = best[side] > p_.cluster_min_size;
        // With no more than cluster_min_size full-length trajectories the side cannot be flagged
        // whatever is there (the thesis' own misses, §6.2.4): no evidence, so unknown, not clear.
        d.valid = d.unsafe || support[side] > p_.cluster_min_size;
        d.unknown = d.valid                                     ? UnknownReason::None
                    : result_.frame_index + 1 < p_.slope_window ? UnknownReason::WarmingUp
                                                                : UnknownReason::TooFewPoints;
        if (!d.valid) d.score = kUnknown;
    }
}

void ThesisClassifier::classify_centre() {
    RegionDecision& d = result_.regions[1];
    d.threshold = p_.centre_slope_threshold;
    const auto& tracks = tracker_.tracks();
    src_.clear();
    dst_.clear();
    centre_tracks_.clear();
    for (std::size_t i = 0; i < tracks.size(); ++i) {
        const Trajectory& t = tracks[i];
        if (t.length < 2 || region_of(t.at_back(0).stab.x) != Region::Centre) continue;
        src_.push_back(t.at_back(1).stab);
        dst_.push_back(t.at_back(0).stab);
        centre_tracks_.push_back(i);
    }
    d.support = static_cast<int>(src_.size());
    double scale = kUnknown;
    if (static_cast<int>(src_.size()) >= std::max(4, p_.homography_min_points)) {
        cv::theRNG().state = 0x5EED5EEDULL;  // RANSAC sampling: same flight, same decisions
        const cv::Mat hm = cv::findHomography(src_, dst_, cv::RANSAC, p_.homography_ransac_px,
                                              inliers_, 2000, 0.995);
        if (!hm.empty()) scale = homography_scale(cv::Matx33d(hm));
    }
    plot(s_scale_raw_, scale);
    if (!std::isnan(scale)) {
        filter_state_ = std::isnan(filter_state_)
                            ? scale
                            : p_.filter_alpha * filter_state_ + (1 - p_.filter_alpha) * scale;
        filtered_.push(filter_state_);
    }
    plot(s_scale_filt_, filter_state_);
    const auto n = static_cast<std::size_t>(p_.fit_window);
    if (filtered_.size() >= n && n <= filtered_.capacity()) {
        xs_.resize(n);
        filtered_.copy_last(n, xs_.data());
        const QuadFit f = fit_quadratic_indexed(xs_);
        if (f.ok) {
            const double nd = static_cast<double>(n);
            d.score = f.slope_at(nd);
            d.valid = true;
            d.unknown = UnknownReason::None;
            d.unsafe = d.score > p_.centre_slope_threshold;
            plot(s_scale_fit_, f.at(nd));
            return;
        }
    }
    d.score = kUnknown;
    d.valid = false;
    d.unknown = filtered_.size() >= n ? UnknownReason::TooFewPoints : UnknownReason::WarmingUp;
    d.unsafe = false;
    plot(s_scale_fit_, kUnknown);
}

void ThesisClassifier::add_overlay_points() {
    const auto& tracks = tracker_.tracks();
    Overlay& o = result_.overlay;
    const double span = std::max(1e-9, p_.colour_max - p_.colour_min);
    for (std::size_t i = 0; i < tracks.size(); ++i) {
        const double s = track_score_[i];
        if (std::isnan(s)) continue;
        o.points.push_back({tracks[i].raw, 4, blue_to_red((s - p_.colour_min) / span), false});
    }
    for (std::size_t i : centre_tracks_) o.points.push_back({tracks[i].raw, 2, kYellow, true});
}

}  // namespace gs::vision
