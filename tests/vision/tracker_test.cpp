// The tracker's spread of trajectories over a grid.

#include "vision/tracker.hpp"

#include "synthetic_helpers.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace gs::vision;
using gs::CameraCalibration;

TEST(TrackerGrid, ABusyBackgroundCannotTakeEverySlot) {
    // Fine, strong texture on the top half of the view only at first; a weakly textured lower
    // half. With the grid every cell holds at most its share and the lower cells get tracks.
    const CameraCalibration c = CameraCalibration::ideal(640, 360, 60);
    cv::Mat img = gs::vision::make_texture(640, 360, 5);
    cv::Mat lower = img(cv::Rect(0, 180, 640, 180));
    lower.convertTo(lower, -1, 0.15, 110);  // low contrast: weaker corners
    for (const bool grid : {false, true}) {
        TrackerParams p;
        p.max_tracks = 120;
        p.detect_interval = 1;
        if (grid) {
            p.grid_cols = 4;
            p.grid_rows = 3;
        }
        TrajectoryTracker t;
        t.configure(c, p);
        for (int f = 0; f < 4; ++f) t.update(img, f * 40'000'000LL, 0, cv::Matx33d::eye());
        int lower_tracks = 0;
        std::vector<int> per_cell(12, 0);
        for (const Trajectory& tr : t.tracks()) {
            lower_tracks += tr.raw.y >= 240 ? 1 : 0;
            const int cx = std::min(3, static_cast<int>(tr.raw.x / 160));
            const int cy = std::min(2, static_cast<int>(tr.raw.y / 120));
            ++per_cell[static_cast<std::size_t>(cy * 4 + cx)];
        }
        if (grid) {
            for (int n : per_cell) EXPECT_LE(n, 10);  // ceil(120 / 12)
            EXPECT_GE(lower_tracks, 30);              // the bottom row's four cells fill up
        } else {
            EXPECT_LT(lower_tracks, 10) << "the test scene should starve the lower half";
        }
    }
}
