// The dataset's CSV and text readers: frames.csv, navdata.csv, labels.csv, the thesis imu.txt,
// raw/video_connections.csv and raw/capture_times.csv. Whatever they accept obeys
// docs/dataset.md 1.1's value rules (finite, within bounds; empty = unknown). Seeds: the shipped
// flight's CSVs and
// ../shared/fixtures/real/navdata_logs (cut to a few KiB).
#include "drone/dataset/dataset.hpp"
#include "drone/dataset/raw_replay.hpp"
#include "drone/dataset/thesis.hpp"
#include "drone/dataset/value_rules.hpp"
#include "fuzz_util.hpp"

#include <cmath>

namespace {
void check(const gs::NavState& s, bool roll_required) {
    auto ok = [](double v, const char* col) {
        if (std::isnan(v)) return true;
        if (!std::isfinite(v)) return false;
        auto b = gs::dataset::value_bounds(col);
        return !b || (v >= b->lo && v <= b->hi);
    };
    GS_FUZZ_CHECK(ok(s.roll_deg, "roll_deg") && ok(s.pitch_deg, "pitch_deg"));
    GS_FUZZ_CHECK(ok(s.vx_mps, "vx_mps") && ok(s.vy_mps, "vy_mps") && ok(s.vz_mps, "vz_mps"));
    GS_FUZZ_CHECK(ok(s.altitude_m, "altitude_m") && !std::isinf(s.yaw_deg));
    (void)roll_required;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto in = gs::fuzz::split(data, size, 6);
    switch (in.choice) {
        case 0:
            if (auto r = gs::dataset::parse_frames_csv(in.text())) {
                gs::TimeNs prev = 0;
                for (std::size_t i = 0; i < r->size(); ++i) {
                    check((*r)[i].nav, true);
                    GS_FUZZ_CHECK(i == 0 || (*r)[i].nav.t_ns >= prev);
                    prev = (*r)[i].nav.t_ns;
                }
            }
            break;
        case 1: {
            std::vector<std::string> warnings;
            if (auto r = gs::dataset::parse_navdata_csv(in.text(), &warnings))
                for (const auto& s : *r) check(s, false);
            break;
        }
        case 2:
            if (auto r = gs::dataset::parse_labels_csv(in.text()))
                for (const auto& l : *r) GS_FUZZ_CHECK(!std::isinf(l.distance_m));
            break;
        case 3:
            (void)gs::dataset::read_thesis_texts(in.text(), "");
            break;
        case 4:
            (void)gs::dataset::parse_video_connections(in.text());
            break;
        default:
            (void)gs::dataset::parse_capture_times(in.text());
            break;
    }
    return 0;
}
