// Renderer: geometry against the camera model, determinism, motion cues (expansion, roll),
// obstacle placement in the image, and that surfaces carry trackable corners.

#include "drone/sim/renderer.hpp"
#include "drone/core/camera_calibration.hpp"
#include "drone/sim/scene.hpp"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace gs::sim {
namespace {

const std::string kRenderScenes = std::string(GS_ASSETS_DIR) + "/scenes/";

Scene load(const std::string& name) {
    auto s = load_scene(kRenderScenes + name);
    EXPECT_TRUE(s.has_value()) << (s ? "" : to_string(s.error()));
    return s ? *s : Scene{};
}

Renderer make(const Scene& s, CameraKind k = CameraKind::Front) {
    auto r = Renderer::create(s,
                              k == CameraKind::Front ? builtin_calibration(CameraId::Front)
                                                     : builtin_calibration(CameraId::Bottom),
                              k);
    EXPECT_TRUE(r.has_value());
    return std::move(r).value();
}

cv::Mat grey(const cv::Mat& bgr) {
    cv::Mat g;
    cv::cvtColor(bgr, g, cv::COLOR_BGR2GRAY);
    return g;
}

TextureSpec plain(cv::Vec3b rgb) {
    TextureSpec t;
    t.kind = TextureKind::Plain;
    t.color_rgb = rgb;
    return t;
}

TEST(SimCalibration, UndistortInvertsDistort) {
    const auto c = builtin_calibration(CameraId::Front);
    for (double x = -0.7; x <= 0.7; x += 0.1)
        for (double y = -0.4; y <= 0.5; y += 0.1) {
            const cv::Point2d px = distort_to_pixel(c, {x, y});
            auto back = undistort_pixel(c, px);
            ASSERT_TRUE(back.has_value());
            EXPECT_NEAR(back->x, x, 1e-9);
            EXPECT_NEAR(back->y, y, 1e-9);
        }
}

TEST(SimCalibration, AssetFilesMatchTheDefaults) {
    for (const auto& [file, def] :
         {std::pair{"ardrone2_front.json", builtin_calibration(CameraId::Front)},
          std::pair{"ardrone2_bottom.json", builtin_calibration(CameraId::Bottom)}}) {
        auto c = load_calibration_file(std::string(GS_ASSETS_DIR) + "/calibration/" + file);
        ASSERT_TRUE(c.has_value()) << to_string(c.error());
        EXPECT_EQ(c->width, 640);
        EXPECT_EQ(c->height, 360);
        EXPECT_DOUBLE_EQ(c->fx, def.fx);
        EXPECT_DOUBLE_EQ(c->fy, def.fy);
        EXPECT_DOUBLE_EQ(c->cx, def.cx);
        EXPECT_DOUBLE_EQ(c->cy, def.cy);
        for (std::size_t i = 0; i < 5; ++i) EXPECT_DOUBLE_EQ(c->dist[i], def.dist[i]) << i;
        EXPECT_FALSE(c->source.empty());
    }
}

// A small white square in a dark room appears where pinhole + distortion put it, not where the
// pinhole alone would.
TEST(SimRender, MarkerProjectsThroughTheDistortionModel) {
    Scene s;
    s.room = Room{};
    s.room.floor = s.room.ceiling = s.room.wall_front = s.room.wall_back = s.room.wall_left =
        s.room.wall_right = plain({20, 20, 20});
    s.lighting.vignette = 0;
    Obstacle m;
    m.shape = ObstacleShape::Box;
    m.x_m = 5.0;
    m.y_m = 2.2;  // well off-axis: the distortion moves it by tens of pixels
    m.z_m = 1.55;
    m.size_x_m = 0.02;
    m.size_y_m = 0.1;
    m.height_m = 0.1;
    m.texture = plain({255, 255, 255});
    s.obstacles.push_back(m);
    Renderer r = make(s);
    const Pose pose{0, 0, 1.0, 0, 0, 0};
    cv::Mat img;
    r.render(pose, img);
    cv::Mat bright = grey(img) > 128;
    const cv::Moments mo = cv::moments(bright, true);
    ASSERT_GT(mo.m00, 20);
    const cv::Point2d found(mo.m10 / mo.m00, mo.m01 / mo.m00);
    // Face centre (4.99, 2.2, 1.6) in the camera frame: x = 2.2, y = -(1.6 - 1.0), z = 4.99.
    const cv::Point2d n(2.2 / 4.99, -0.6 / 4.99);
    const auto c = builtin_calibration(CameraId::Front);
    const cv::Point2d expect = distort_to_pixel(c, n);
    const cv::Point2d pinhole(c.fx * n.x + c.cx, c.fy * n.y + c.cy);
    EXPECT_NEAR(found.x, expect.x, 1.0);
    EXPECT_NEAR(found.y, expect.y, 1.0);
    EXPECT_GT(cv::norm(pinhole - expect), 15.0);  // the test can tell the models apart
    const auto proj = r.project(pose, 4.99, 2.2, 1.6);
    ASSERT_TRUE(proj.has_value());
    EXPECT_NEAR(proj->x, expect.x, 1e-9);
}

TEST(SimRender, SamePoseGivesIdenticalBytes) {
    // A small scene: building a renderer generates every texture, which the sanitizer build
    // pays dearly for with the warehouse's hundreds of objects.
    const Scene s = load("thesis_pillar_left.json");
    Renderer a = make(s);
    Renderer b = make(s);
    const Pose p{3.2, 0.1, 1.3, 2.5, -3.0, 4.0};
    cv::Mat i1, i2, i3;
    a.render(p, i1);
    a.render(Pose{5, 0, 1, 0, 0, 0}, i2);
    a.render(p, i2);
    b.render(p, i3);
    EXPECT_EQ(cv::norm(i1, i2, cv::NORM_INF), 0);
    EXPECT_EQ(cv::norm(i1, i3, cv::NORM_INF), 0);
    EXPECT_GT(cv::norm(grey(i1), cv::NORM_L1) / double(i1.total()), 30);  // not blank
}

// Flying forward makes tracked corners move away from the principal point (focus of expansion),
// the faster the further out; the scene gives the tracker plenty of corners.
TEST(SimRender, ForwardMotionExpandsAboutThePrincipalPoint) {
    const Scene s = load("thesis_open_hall.json");
    Renderer r = make(s);
    cv::Mat a, b;
    r.render(Pose{0, 0, 1.2, 0, 0, 0}, a);
    r.render(Pose{0.3, 0, 1.2, 0, 0, 0}, b);
    std::vector<cv::Point2f> p0, p1;
    cv::goodFeaturesToTrack(grey(a), p0, 400, 0.01, 8);
    ASSERT_GE(p0.size(), 150u);
    std::vector<uchar> st;
    std::vector<float> err;
    cv::calcOpticalFlowPyrLK(grey(a), grey(b), p0, p1, st, err);
    const auto c = builtin_calibration(CameraId::Front);
    const cv::Point2d pp(c.cx, c.cy);
    int tracked = 0, outward = 0;
    for (std::size_t i = 0; i < p0.size(); ++i) {
        if (!st[i]) continue;
        const cv::Point2d d = cv::Point2d(p0[i]) - pp, f = cv::Point2d(p1[i] - p0[i]);
        if (cv::norm(d) < 40) continue;  // near the FOE the flow is tiny and direction noisy
        ++tracked;
        if (d.dot(f) > 0) ++outward;
    }
    ASSERT_GE(tracked, 100);
    EXPECT_GE(double(outward) / tracked, 0.95) << outward << "/" << tracked;
}

// Share of dark (pillar) pixels in a band of rows, by image column range.
double dark_share(const cv::Mat& g, int x0, int x1) {
    const cv::Mat band = g(cv::Range(120, 200), cv::Range(x0, x1));
    return cv::countNonZero(band < 50) / double(band.total());
}

TEST(SimRender, PillarLeftAppearsInTheLeftOfTheImage) {
    const Pose p{4.5, 0, 1.0, 0, 0, 0};  // 2.5 m before the pillar's near face
    cv::Mat left, right;
    Renderer rl = make(load("thesis_pillar_left.json"));
    Renderer rr = make(load("thesis_pillar_right.json"));
    rl.render(p, left);
    rr.render(p, right);
    // Pillar 0.5 m wide, centre 0.5 m to the side, near face 2.5 m ahead: it spans about
    // 0.25..0.75 m / 2.5 m -> 0.1..0.3 in normalised x, ~ 60..170 px from cx.
    EXPECT_GT(dark_share(grey(left), 180, 260), 0.4);
    EXPECT_LT(dark_share(grey(left), 340, 640), 0.02);
    EXPECT_GT(dark_share(grey(right), 400, 480), 0.4);
    EXPECT_LT(dark_share(grey(right), 0, 320), 0.02);
}

// Roll about the optical axis rotates the image: right side down moves the right of the image
// up, i.e. a negative angle in image coordinates (y down).
TEST(SimRender, RollRotatesTheImage) {
    const Scene s = load("thesis_open_hall.json");
    Renderer r = make(s);
    cv::Mat a, b;
    r.render(Pose{0, 0, 1.2, 0, 0, 0}, a);
    r.render(Pose{0, 0, 1.2, 10.0, 0, 0}, b);
    std::vector<cv::Point2f> p0, p1;
    cv::goodFeaturesToTrack(grey(a), p0, 300, 0.01, 8);
    std::vector<uchar> st;
    std::vector<float> err;
    cv::calcOpticalFlowPyrLK(grey(a), grey(b), p0, p1, st, err, cv::Size(31, 31), 4);
    const auto c = builtin_calibration(CameraId::Front);
    std::vector<cv::Point2f> u0, u1;  // undistorted normalised coordinates
    for (std::size_t i = 0; i < p0.size(); ++i) {
        if (!st[i]) continue;
        auto a0 = undistort_pixel(c, p0[i]);
        auto a1 = undistort_pixel(c, p1[i]);
        if (a0 && a1) {
            u0.emplace_back(*a0);
            u1.emplace_back(*a1);
        }
    }
    ASSERT_GE(u0.size(), 50u);
    const cv::Mat m = cv::estimateAffinePartial2D(u0, u1, cv::noArray(), cv::RANSAC, 0.003);
    ASSERT_FALSE(m.empty());
    const double angle = std::atan2(m.at<double>(1, 0), m.at<double>(0, 0)) * 180 / CV_PI;
    EXPECT_NEAR(angle, -10.0, 0.5);
}

TEST(SimRender, BottomCameraSeesTheFloorScaleWithHeight) {
    const Scene s = load("thesis_open_hall.json");
    Renderer r = make(s, CameraKind::Bottom);
    cv::Mat a, b;
    r.render(Pose{0, 0, 1.0, 0, 0, 0}, a);
    r.render(Pose{0.1, 0, 1.0, 0, 0, 0}, b);
    // Forward 0.1 m at 1 m height: the floor slides towards the image bottom by ~fy * 0.1 px.
    std::vector<cv::Point2f> p0, p1;
    cv::goodFeaturesToTrack(grey(a), p0, 200, 0.01, 8);
    ASSERT_GE(p0.size(), 30u);
    std::vector<uchar> st;
    std::vector<float> err;
    cv::calcOpticalFlowPyrLK(grey(a), grey(b), p0, p1, st, err, cv::Size(31, 31), 4);
    std::vector<double> dy;
    for (std::size_t i = 0; i < p0.size(); ++i)
        if (st[i] && std::abs(p0[i].x - 320) < 120 && std::abs(p0[i].y - 219) < 80)
            dy.push_back(static_cast<double>(p1[i].y - p0[i].y));
    ASSERT_GE(dy.size(), 10u);
    std::nth_element(dy.begin(), dy.begin() + long(dy.size() / 2), dy.end());
    EXPECT_NEAR(dy[dy.size() / 2], 70.2, 4.0);  // fy 701.65 x 0.1 m / 1 m
}

TEST(SimRender, TopCameraSeesTheCeilingMirroredAcross) {
    const Scene s = load("thesis_open_hall.json");  // ceiling at 8 m
    Renderer r = make(s, CameraKind::Top);
    cv::Mat a, b;
    r.render(Pose{0, 0, 5.0, 0, 0, 0}, a);
    r.render(Pose{0.1, 0.1, 5.0, 0, 0, 0}, b);
    // 3 m below the ceiling, 0.1 m forward and 0.1 m right: the ceiling slides towards the image
    // bottom (forward is up) and to the image RIGHT (right is to the left) by ~f * 0.1 / 3 px.
    std::vector<cv::Point2f> p0, p1;
    cv::goodFeaturesToTrack(grey(a), p0, 300, 0.01, 8);
    ASSERT_GE(p0.size(), 30u);
    std::vector<uchar> st;
    std::vector<float> err;
    cv::calcOpticalFlowPyrLK(grey(a), grey(b), p0, p1, st, err, cv::Size(31, 31), 4);
    std::vector<double> dx, dy;
    for (std::size_t i = 0; i < p0.size(); ++i)
        if (st[i] && std::abs(p0[i].x - 320) < 120 && std::abs(p0[i].y - 219) < 80) {
            dx.push_back(static_cast<double>(p1[i].x - p0[i].x));
            dy.push_back(static_cast<double>(p1[i].y - p0[i].y));
        }
    ASSERT_GE(dx.size(), 10u);
    auto median = [](std::vector<double> v) {
        std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
        return v[v.size() / 2];
    };
    EXPECT_NEAR(median(dx), 23.35, 2.0);  // fx 700.49 x 0.1 / 3
    EXPECT_NEAR(median(dy), 23.39, 2.0);  // fy 701.65 x 0.1 / 3
}

// A glossy floor mirrors the scene above it: below the black pillar's base the floor shows the
// pillar's reflection, point for point (the pillar at height h appears where a point h below the
// floor would); off, the render is byte-identical to a matte one.
TEST(SimRender, GlossyFloorMirrorsThePillarAndOffChangesNothing) {
    const Scene s = load("thesis_pillar_center.json");
    const Pose p{2.0, 0, 1.0, 0, 0, 0};  // 5 m before the pillar's near face (x = 7)
    RenderOptions gloss;
    gloss.floor_reflection = 0.5;
    Renderer matte_r = make(s);
    auto gloss_r =
        Renderer::create(s, builtin_calibration(CameraId::Front), CameraKind::Front, gloss);
    ASSERT_TRUE(gloss_r);
    cv::Mat matte, glossy;
    matte_r.render(p, matte);
    gloss_r->render(p, glossy);
    RenderOptions zero;
    zero.floor_reflection = 0;
    zero.floor_blur_deg = 1.5;
    auto zero_r =
        Renderer::create(s, builtin_calibration(CameraId::Front), CameraKind::Front, zero);
    cv::Mat off;
    zero_r->render(p, off);
    EXPECT_EQ(cv::norm(matte, off, cv::NORM_L1), 0) << "off must leave the render unchanged";
    const cv::Mat gm = grey(matte), gg = grey(glossy);
    // Along the pillar's near face, heights 0.05 .. 0.8 m: the reflection (glossy minus half the
    // matte floor, doubled) against the pillar seen directly.
    std::vector<double> direct, reflected;
    double floor_drop = 0;
    for (double h = 0.05; h < 0.8; h += 0.025)
        for (double y = -0.2; y <= 0.2; y += 0.1) {
            const auto up = matte_r.project(p, 7.0, y, h);
            const auto down = matte_r.project(p, 7.0, y, -h);
            ASSERT_TRUE(up && down);
            const cv::Point a(int(std::lround(up->x)), int(std::lround(up->y)));
            const cv::Point b(int(std::lround(down->x)), int(std::lround(down->y)));
            ASSERT_TRUE(cv::Rect(0, 0, 640, 360).contains(b));
            direct.push_back(gm.at<std::uint8_t>(a));
            reflected.push_back(2.0 * gg.at<std::uint8_t>(b) - gm.at<std::uint8_t>(b));
            floor_drop += double(gm.at<std::uint8_t>(b)) - double(gg.at<std::uint8_t>(b));
        }
    const double n = double(direct.size());
    double ma = 0, mb = 0;
    for (std::size_t i = 0; i < direct.size(); ++i) {
        ma += direct[i] / n;
        mb += reflected[i] / n;
    }
    double sab = 0, saa = 0, sbb = 0;
    for (std::size_t i = 0; i < direct.size(); ++i) {
        sab += (direct[i] - ma) * (reflected[i] - mb);
        saa += (direct[i] - ma) * (direct[i] - ma);
        sbb += (reflected[i] - mb) * (reflected[i] - mb);
    }
    const double corr = sab / std::sqrt(saa * sbb);
    EXPECT_GT(corr, 0.6) << "the reflection follows the pillar's pattern";
    EXPECT_NEAR(mb, ma, 15) << "the reflection has the pillar's brightness";
    EXPECT_GT(floor_drop / n, 30) << "the black pillar darkens the floor under it";
    // Away from the floor (the pillar itself, the walls) nothing changes.
    const auto face = matte_r.project(p, 7.0, 0.1, 1.5);
    ASSERT_TRUE(face);
    EXPECT_EQ(gm.at<std::uint8_t>(cv::Point(int(face->x), int(face->y))),
              gg.at<std::uint8_t>(cv::Point(int(face->x), int(face->y))));
    EXPECT_EQ(cv::norm(matte.rowRange(0, 60), glossy.rowRange(0, 60), cv::NORM_L1), 0)
        << "the top rows see no floor";
    std::printf(
        "glossy floor: correlation %.3f, reflection mean %.1f vs pillar %.1f, floor "
        "darker by %.1f\n",
        corr, mb, ma, floor_drop / n);
}

}  // namespace
}  // namespace gs::sim
