#pragma once
// A recorded dataset played back as the same stream of samples the live link produces: frames
// (pixels from a FrameStore) with their frames.csv state, and navdata samples (navdata.csv, else
// the frames' own attitude), paced at recorded speed x factor or as fast as possible; seek, step.

#include "drone/core/sample_source.hpp"
#include "drone/dataset/dataset.hpp"
#include "drone/dataset/frame_store.hpp"

#include <memory>

namespace gs::dataset {

class DatasetSource final : public SampleSource {
public:
    // `clock` must outlive the source. A consumer that falls more than `max_lag_ns` behind the
    // recorded pace is re-anchored (playback slows down rather than bursting to catch up).
    DatasetSource(Dataset dataset, std::unique_ptr<FrameStore> frames, const Clock& clock,
                  Pacing pacing = Pacing::realtime(), TimeNs max_lag_ns = 500'000'000);

    SourceStatus next(FrameSample& out) override;
    SourceStatus next_nav(NavState& out) override;
    TimeNs wait_hint_ns() const override { return wait_hint_ns_; }
    std::optional<std::int64_t> frame_count() const override { return dataset_.frame_count(); }
    bool seek(std::int64_t frame) override;
    SourceStatus step(FrameSample& out) override;
    void set_pacing(Pacing p) override;
    void set_paused(bool paused) override;
    std::string last_error() const override { return last_error_; }

    const Dataset& dataset() const { return dataset_; }
    std::int64_t position() const { return next_frame_; }  // index next() returns next
    // Frames that could not be read (each reported once as Error, then skipped).
    std::int64_t read_errors() const { return errors_; }

private:
    TimeNs media_now();
    void anchor(TimeNs media_ns);
    SourceStatus deliver(FrameSample& out);
    const std::vector<NavState>& navs() const { return navs_; }

    Dataset dataset_;
    std::unique_ptr<FrameStore> frames_;
    const Clock& clock_;
    Pacing pacing_;
    TimeNs max_lag_ns_;
    std::vector<NavState> navs_;  // the navdata stream (navdata.csv or the frames' states)
    std::int64_t next_frame_ = 0;
    std::size_t next_nav_ = 0;
    bool anchored_ = false;
    TimeNs anchor_media_ns_ = 0;
    TimeNs anchor_wall_ns_ = 0;
    bool paused_ = false;
    TimeNs paused_media_ns_ = 0;
    TimeNs wait_hint_ns_ = 0;
    std::string last_error_;
    std::int64_t errors_ = 0;
    cv::Mat image_;
};

}  // namespace gs::dataset
