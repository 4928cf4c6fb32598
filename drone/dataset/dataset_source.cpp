#include "drone/dataset/dataset_source.hpp"

#include <algorithm>

namespace gs::dataset {

DatasetSource::DatasetSource(Dataset dataset, std::unique_ptr<FrameStore> frames,
                             const Clock& clock, Pacing pacing, TimeNs max_lag_ns)
    : dataset_(std::move(dataset)),
      frames_(std::move(frames)),
      clock_(clock),
      pacing_(pacing),
      max_lag_ns_(max_lag_ns) {
    pacing_.speed = std::clamp(pacing_.speed, Pacing::kMinSpeed, Pacing::kMaxSpeed);
    if (dataset_.has_navdata()) {
        navs_ = dataset_.navdata();
    } else {
        navs_.reserve(dataset_.frames().size());
        for (const auto& r : dataset_.frames()) navs_.push_back(r.nav);
    }
}

void DatasetSource::anchor(TimeNs media_ns) {
    anchored_ = true;
    anchor_media_ns_ = media_ns;
    anchor_wall_ns_ = clock_.now_ns();
}

TimeNs DatasetSource::media_now() {
    if (paused_) return paused_media_ns_;
    if (!anchored_) {
        const auto& rows = dataset_.frames();
        anchor(next_frame_ < dataset_.frame_count()
                   ? rows[static_cast<std::size_t>(next_frame_)].nav.t_ns
                   : (rows.empty() ? 0 : rows.back().nav.t_ns));
    }
    const double elapsed = static_cast<double>(clock_.now_ns() - anchor_wall_ns_);
    return anchor_media_ns_ + static_cast<TimeNs>(elapsed * pacing_.speed);
}

SourceStatus DatasetSource::deliver(FrameSample& out) {
    const auto& row = dataset_.frames()[static_cast<std::size_t>(next_frame_)];
    if (auto e = frames_->read(next_frame_, image_)) {
        // The frame is skipped: the caller counts it, and the next call goes on after it.
        last_error_ = "frame " + std::to_string(next_frame_) + ": " + to_string(*e);
        ++next_frame_;
        ++errors_;
        return SourceStatus::Error;
    }
    out.index = next_frame_;
    out.t_ns = row.nav.t_ns;
    // A recording has no receive time (FrameSample: 0, not applicable): its frames are timed by
    // their capture alone, t_ns; the pacing clock says when it was played, not when it arrived.
    out.recv_ns = 0;
    out.capture_ns = 0;
    out.frame_number.reset();
    out.image = image_;
    out.nav = row.nav;
    out.concealed = frames_->last_concealed();
    out.repaired = frames_->last_repaired();
    ++next_frame_;
    return SourceStatus::Sample;
}

SourceStatus DatasetSource::next(FrameSample& out) {
    wait_hint_ns_ = 0;
    if (next_frame_ >= dataset_.frame_count()) return SourceStatus::End;
    if (paused_) return SourceStatus::Paused;
    const TimeNs due = dataset_.frames()[static_cast<std::size_t>(next_frame_)].nav.t_ns;
    if (pacing_.as_fast_as_possible) {
        // Media time follows the frames; next_nav() yields navdata up to the next frame's capture.
        anchor(due);
        return deliver(out);
    }
    const TimeNs now_media = media_now();
    if (due > now_media) {
        wait_hint_ns_ = static_cast<TimeNs>(static_cast<double>(due - now_media) / pacing_.speed);
        return SourceStatus::NotYet;
    }
    if (now_media - due > max_lag_ns_) anchor(due);
    return deliver(out);
}

SourceStatus DatasetSource::next_nav(NavState& out) {
    if (next_nav_ >= navs_.size()) return SourceStatus::End;
    if (paused_) return SourceStatus::Paused;
    TimeNs limit;
    if (pacing_.as_fast_as_possible) {
        limit = next_frame_ < dataset_.frame_count()
                    ? dataset_.frames()[static_cast<std::size_t>(next_frame_)].nav.t_ns
                    : navs_.back().t_ns;
    } else {
        limit = media_now();
    }
    if (navs_[next_nav_].t_ns > limit) return SourceStatus::NotYet;
    out = navs_[next_nav_++];
    return SourceStatus::Sample;
}

bool DatasetSource::seek(std::int64_t frame) {
    if (frame < 0 || frame >= dataset_.frame_count()) return false;
    next_frame_ = frame;
    const TimeNs t = dataset_.frames()[static_cast<std::size_t>(frame)].nav.t_ns;
    // Navdata resumes at the last sample before that frame's capture (the state it was taken in).
    auto it = std::upper_bound(navs_.begin(), navs_.end(), t,
                               [](TimeNs v, const NavState& s) { return v < s.t_ns; });
    if (it != navs_.begin()) --it;
    next_nav_ = static_cast<std::size_t>(it - navs_.begin());
    if (paused_) {
        paused_media_ns_ = t;
    } else {
        anchor(t);
    }
    return true;
}

SourceStatus DatasetSource::step(FrameSample& out) {
    if (next_frame_ >= dataset_.frame_count()) return SourceStatus::End;
    const TimeNs t = dataset_.frames()[static_cast<std::size_t>(next_frame_)].nav.t_ns;
    if (paused_) {
        paused_media_ns_ = t;
    } else {
        anchor(t);
    }
    return deliver(out);
}

void DatasetSource::set_pacing(Pacing p) {
    p.speed = std::clamp(p.speed, Pacing::kMinSpeed, Pacing::kMaxSpeed);
    if (!paused_ && anchored_) anchor(media_now());
    pacing_ = p;
}

void DatasetSource::set_paused(bool paused) {
    if (paused == paused_) return;
    if (paused) {
        paused_media_ns_ = media_now();
        paused_ = true;
    } else {
        paused_ = false;
        anchor(paused_media_ns_);
    }
}

}  // namespace gs::dataset
