// The drone state at a frame's capture time: interpolated between the samples around it, the
// nearest when there is none on one side, and unknown when no sample is within the allowed gap
// (a navdata blackout), never an old sample relabelled.

#include "drone/core/nav_timeline.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace gs {
namespace {

NavState sample(TimeNs t_ns, double roll) {
    NavState s;
    s.t_ns = t_ns;
    s.roll_deg = roll;
    s.vx_mps = roll / 10;
    s.altitude_m = 1;
    return s;
}

constexpr TimeNs kMs = 1'000'000;

TEST(NavTimeline, InterpolatesBetweenSamplesAndTakesTheNearestAtTheEnds) {
    NavTimeline tl;
    tl.push(sample(100 * kMs, 1));
    tl.push(sample(200 * kMs, 3));
    EXPECT_DOUBLE_EQ(tl.state_at(150 * kMs).roll_deg, 2);
    EXPECT_DOUBLE_EQ(tl.state_at(50 * kMs).roll_deg, 1);
    const NavState late = tl.state_at(5000 * kMs);  // no limit: the newest, relabelled
    EXPECT_DOUBLE_EQ(late.roll_deg, 3);
    EXPECT_EQ(late.t_ns, 5000 * kMs);
}

TEST(NavTimeline, NoSampleWithinTheGapIsUnknownNotAnOldSampleRelabelled) {
    NavTimeline tl;
    tl.push(sample(100 * kMs, 1));
    tl.push(sample(200 * kMs, 3));
    tl.push(sample(3200 * kMs, 9));  // 3 s of blackout before this one
    const TimeNs gap = kFrameNavMaxGapNs;
    // Near a sample on one side only: that sample.
    EXPECT_DOUBLE_EQ(tl.state_at(600 * kMs, gap).roll_deg, 3);
    EXPECT_DOUBLE_EQ(tl.state_at(2800 * kMs, gap).roll_deg, 9);
    // In the middle of the blackout: unknown, with the asked time.
    const NavState mid = tl.state_at(1700 * kMs, gap);
    EXPECT_TRUE(std::isnan(mid.roll_deg));
    EXPECT_TRUE(std::isnan(mid.vx_mps));
    EXPECT_TRUE(std::isnan(mid.altitude_m));
    EXPECT_EQ(mid.t_ns, 1700 * kMs);
    // Past the newest sample by more than the gap (the link lost): unknown; within it: nearest.
    EXPECT_TRUE(std::isnan(tl.state_at(3800 * kMs, gap).roll_deg));
    EXPECT_DOUBLE_EQ(tl.state_at(3600 * kMs, gap).roll_deg, 9);
    // Both neighbours near: interpolated as without a limit.
    EXPECT_DOUBLE_EQ(tl.state_at(150 * kMs, gap).roll_deg, 2);
    // Before the first sample by more than the gap: unknown.
    EXPECT_TRUE(std::isnan(tl.state_at(0, 50 * kMs).roll_deg));
}

// Issue 14 point 2: "alignment never uses a sample older than one already used". Once a sample
// has been used (state_at interpolated with it), a sample from before it that arrives later (a
// late or duplicated packet the caller failed to drop) changes nothing: it is not inserted
// between the two it falls between, it does not become the newest, and it takes no place in the
// ring. Sequence numbers are the link's to check (LinkStateMachine::on_navdata drops a late or
// duplicated sequence before any sample reaches a timeline); the timeline orders by time.
TEST(NavTimeline, ASampleOlderThanOneAlreadyUsedIsIgnored) {
    NavTimeline tl(3);
    NavState a = sample(100 * kMs, 1), b = sample(200 * kMs, 3);
    a.seq = 10;
    b.seq = 11;
    tl.push(a);
    tl.push(b);
    ASSERT_DOUBLE_EQ(tl.state_at(150 * kMs).roll_deg, 2);  // both used

    NavState late = sample(150 * kMs, 50);  // between the two, arriving after them
    late.seq = 9;
    tl.push(late);
    NavState dup = sample(100 * kMs, -40);  // the first one's time again, other values
    dup.seq = 10;
    tl.push(dup);
    EXPECT_EQ(tl.size(), 2u);
    EXPECT_EQ(tl.newest_t(), 200 * kMs);
    EXPECT_DOUBLE_EQ(tl.state_at(150 * kMs).roll_deg, 2);
    EXPECT_DOUBLE_EQ(tl.state_at(125 * kMs).roll_deg, 1.5);
    EXPECT_DOUBLE_EQ(tl.state_at(100 * kMs).roll_deg, 1);
    EXPECT_EQ(tl.state_at(175 * kMs).seq, b.seq);  // nearest sample's sequence: the newer one

    // The next sample in order is taken, and the ring's capacity (3) went to it, not to the
    // ignored ones: the first sample is still there.
    NavState c = sample(300 * kMs, 5);
    c.seq = 12;
    tl.push(c);
    EXPECT_EQ(tl.size(), 3u);
    EXPECT_DOUBLE_EQ(tl.state_at(250 * kMs).roll_deg, 4);
    EXPECT_DOUBLE_EQ(tl.state_at(100 * kMs).roll_deg, 1);
    // And a late one after it is ignored too, with the ring full.
    tl.push(sample(250 * kMs, 70));
    EXPECT_EQ(tl.newest_t(), 300 * kMs);
    EXPECT_DOUBLE_EQ(tl.state_at(250 * kMs).roll_deg, 4);
    EXPECT_DOUBLE_EQ(tl.state_at(100 * kMs).roll_deg, 1);
}

}  // namespace
}  // namespace gs
