// What the classifier does with frames it cannot fully trust (issue 14 points 3 and 8): a frame
// whose time is not after the previous one is rejected (no motion is measured over a zero or
// negative step), and a frame decoded with concealed damage may keep an alarm but not raise one.

#include "synthetic_helpers.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace gs::vision;
using namespace gs::vision::test;

namespace {

// Frame i of flight `f` as the classifier receives it, at time `t_ns`.
FrameInput frame_of(const Flight& f, int i, std::int64_t t_ns, cv::Mat& img) {
    const CameraPose pose = f.pose_at(i);
    render_scene(f.planes, synthetic_calibration(), pose, img);
    FrameInput in;
    in.image = img;
    in.t_ns = t_ns;
    in.attitude = {pose.roll_deg, pose.pitch_deg, pose.yaw_deg};
    in.vx_mps = 1.0;  // the approach is flown at 1 m/s
    in.vy_mps = 0;
    in.vz_mps = 0;
    return in;
}

std::int64_t time_of(const Flight& f, int i) {
    return static_cast<std::int64_t>(std::llround(i * 1e9 / f.fps));
}

// The first frame of the approach at which `flow` turns the centre unsafe (clean frames).
int first_alarm(const Flight& f) {
    auto c = make_classifier("flow", synthetic_calibration());
    cv::Mat img;
    for (int i = 0; i < f.frames; ++i) {
        const FrameResult& r = c->process(frame_of(f, i, time_of(f, i), img));
        if (r.regions[1].valid && r.regions[1].unsafe) return i;
    }
    return -1;
}

}  // namespace

TEST(ClassifierTrust, AFrameNotAfterThePreviousIsRejectedAndMeasuresNothing) {
    for (const char* name : {"flow", "thesis"}) {
        const Flight f = make_flight(Motion::Approach);
        auto c = make_classifier(name, synthetic_calibration());
        cv::Mat img;
        const int n = 40;
        for (int i = 0; i < n; ++i) (void)c->process(frame_of(f, i, time_of(f, i), img));
        const FrameResult before = c->process(frame_of(f, n, time_of(f, n), img));
        ASSERT_EQ(before.rejected_steps, 0) << name;
        // The next frame's picture at the same time (frames sharing a capture time), then one
        // stamped earlier (a clock that stepped back): neither is measured.
        for (const std::int64_t t : {time_of(f, n), time_of(f, n) - 1'000'000}) {
            const FrameResult& r = c->process(frame_of(f, n + 1, t, img));
            EXPECT_EQ(r.frame_index, before.frame_index) << name;
            EXPECT_EQ(r.t_ns, before.t_ns) << name;
            for (std::size_t k = 0; k < 3; ++k) {
                EXPECT_EQ(r.regions[k].unsafe, before.regions[k].unsafe) << name << " " << k;
                EXPECT_EQ(r.regions[k].valid, before.regions[k].valid) << name << " " << k;
            }
        }
        // A frame after it is measured again, over the step from the last accepted frame.
        const FrameResult& next = c->process(frame_of(f, n + 1, time_of(f, n + 1), img));
        EXPECT_EQ(next.rejected_steps, 2) << name;
        EXPECT_EQ(next.frame_index, before.frame_index + 1) << name;
    }
}

TEST(ClassifierTrust, AConcealedFrameKeepsAnAlarmButCannotRaiseOne) {
    const Flight f = make_flight(Motion::Approach);
    const int k = first_alarm(f);
    ASSERT_GT(k, 5) << "flow never flagged the approach";
    ASSERT_LT(k + 3, f.frames);

    auto c = make_classifier("flow", synthetic_calibration());
    cv::Mat img;
    for (int i = 0; i < k; ++i) (void)c->process(frame_of(f, i, time_of(f, i), img));
    // The frame that would raise the alarm arrives damaged: unknown, not unsafe.
    FrameInput damaged = frame_of(f, k, time_of(f, k), img);
    damaged.concealed = true;
    const FrameResult& r = c->process(damaged);
    EXPECT_FALSE(r.regions[1].unsafe);
    EXPECT_FALSE(r.regions[1].valid);
    EXPECT_EQ(r.regions[1].unknown, UnknownReason::DamagedFrame);
    // The next clean frame agrees: the alarm rises.
    const FrameResult& clean = c->process(frame_of(f, k + 1, time_of(f, k + 1), img));
    EXPECT_TRUE(clean.regions[1].valid && clean.regions[1].unsafe);
    // A damaged frame while the alarm stands keeps it.
    FrameInput damaged2 = frame_of(f, k + 2, time_of(f, k + 2), img);
    damaged2.concealed = true;
    const FrameResult& kept = c->process(damaged2);
    EXPECT_TRUE(kept.regions[1].valid && kept.regions[1].unsafe);
}
