// drone/calibration: the one calibration record: JSON in the flight.json / assets shape, save and
// load round trip, defaults from assets, scaling, and the distortion helpers.

#include "drone/core/calibration.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace gs {
namespace {
namespace fs = std::filesystem;

struct TempFile {
    fs::path path;
    explicit TempFile(const std::string& name) {
        std::string tmpl = (fs::temp_directory_path() / "gs_calib_XXXXXX").string();
        const char* d = ::mkdtemp(tmpl.data());
        EXPECT_NE(d, nullptr);
        path = fs::path(tmpl) / name;
    }
    ~TempFile() {
        std::error_code ec;
        fs::remove_all(path.parent_path(), ec);
    }
    void write(const std::string& text) const { std::ofstream(path) << text; }
};

TEST(Calibration, ParsesTheFlightJsonShape) {
    auto c = calibration_from_json(nlohmann::json::parse(
        R"({"fx": 571.37, "fy": 569.36, "cx": 329.85, "cy": 177.76,
            "dist": [-0.5176, 0.2687, 0.0001, 0.0013, 0.0]})"));
    ASSERT_TRUE(c);
    EXPECT_EQ(c->fx, 571.37);
    EXPECT_EQ(c->cy, 177.76);
    EXPECT_EQ(c->dist[0], -0.5176);
    EXPECT_EQ(c->dist[3], 0.0013);
    EXPECT_EQ(c->width, 0);  // size unknown: it is the flight's
    EXPECT_FALSE(c->valid());
}

TEST(Calibration, RejectsBadObjectsNamingTheKey) {
    auto parse = [](const char* text) {
        return calibration_from_json(nlohmann::json::parse(text));
    };
    auto a = parse(R"({"fx": 1, "fy": 1, "cx": 0})");
    ASSERT_FALSE(a);
    EXPECT_EQ(a.error().key, "cy");
    EXPECT_EQ(a.error().code, DatasetErrorCode::Missing);
    auto b = parse(R"({"fx": -1, "fy": 1, "cx": 0, "cy": 0})");
    ASSERT_FALSE(b);
    EXPECT_EQ(b.error().code, DatasetErrorCode::OutOfRange);
    auto d = parse(R"({"fx": 1, "fy": 1, "cx": 0, "cy": 0, "dist": [1, 2, 3]})");
    ASSERT_FALSE(d);
    EXPECT_EQ(d.error().key, "dist");
    auto w = parse(R"({"fx": 1, "fy": 1, "cx": 0, "cy": 0, "width": 640})");
    ASSERT_FALSE(w);
    EXPECT_EQ(w.error().key, "height");
    auto s = parse(R"({"fx": 1, "fy": 1, "cx": "0", "cy": 0})");
    ASSERT_FALSE(s);
    EXPECT_EQ(s.error().key, "cx");
    EXPECT_EQ(s.error().code, DatasetErrorCode::Malformed);
}

TEST(Calibration, SaveLoadRoundTrip) {
    TempFile f("cam.json");
    CameraCalibration c = builtin_calibration(CameraId::Front);
    c.source = "test \"quoted\"";
    ASSERT_FALSE(save_calibration_file(f.path, c));
    auto back = load_calibration_file(f.path);
    ASSERT_TRUE(back) << to_string(back.error());
    EXPECT_EQ(back->fx, c.fx);
    EXPECT_EQ(back->fy, c.fy);
    EXPECT_EQ(back->cx, c.cx);
    EXPECT_EQ(back->cy, c.cy);
    EXPECT_EQ(back->dist, c.dist);
    EXPECT_EQ(back->width, 640);
    EXPECT_EQ(back->height, 360);
    EXPECT_EQ(back->source, c.source);
}

TEST(Calibration, FileErrorsNameFileAndLine) {
    TempFile f("bad.json");
    f.write("{\n  \"fx\": 1, \"fy\": 1, \"cx\": 0, \"cy\": 0,\n  \"dist\": [1]\n}\n");
    auto e = load_calibration_file(f.path);
    ASSERT_FALSE(e);
    EXPECT_EQ(
        to_string(e.error()),
        f.path.string() + ":3:3: 'dist': expected an array of 4 or 5 numbers (k1, k2, p1, p2, k3)");
    auto missing = load_calibration_file(f.path.parent_path() / "nope.json");
    ASSERT_FALSE(missing);
    EXPECT_EQ(missing.error().code, DatasetErrorCode::Missing);
}

TEST(Calibration, DefaultsComeFromTheAssets) {
    auto front = default_calibration(CameraId::Front);
    ASSERT_TRUE(front) << to_string(front.error());
    const CameraCalibration b = builtin_calibration(CameraId::Front);
    EXPECT_EQ(front->fx, b.fx);
    EXPECT_EQ(front->dist, b.dist);
    EXPECT_TRUE(front->valid());
    auto bottom = default_calibration(CameraId::Bottom);
    ASSERT_TRUE(bottom);
    EXPECT_EQ(bottom->fy, builtin_calibration(CameraId::Bottom).fy);
    EXPECT_FALSE(default_calibration(CameraId::Front, "/nonexistent"));
}

TEST(Calibration, ScaledToKeepsPixelCentres) {
    CameraCalibration c;
    c.fx = 560;
    c.fy = 500;
    c.cx = 319.5;
    c.cy = 179.5;
    c.width = 640;
    c.height = 360;
    c.dist = {-0.5, 0.2, 0, 0, 0};
    const CameraCalibration h = scaled_to(c, 320, 180);
    EXPECT_EQ(h.fx, 280);
    EXPECT_EQ(h.fy, 250);
    EXPECT_EQ(h.cx, 159.5);  // (319.5 + 0.5) / 2 - 0.5: still the image centre
    EXPECT_EQ(h.cy, 89.5);
    EXPECT_EQ(h.dist, c.dist);
    EXPECT_EQ(h.width, 320);
    // an unknown source size is taken as the target size
    c.width = c.height = 0;
    const CameraCalibration u = scaled_to(c, 320, 180);
    EXPECT_EQ(u.fx, 560);
    EXPECT_EQ(u.width, 320);
}

TEST(Calibration, DistortionHelpersInvertEachOther) {
    const CameraCalibration c = builtin_calibration(CameraId::Front);
    // the principal point is a fixed point of the model
    const cv::Point2d pp = distort_to_pixel(c, {0, 0});
    EXPECT_DOUBLE_EQ(pp.x, c.cx);
    EXPECT_DOUBLE_EQ(pp.y, c.cy);
    // k1 < 0: barrel distortion pulls an off-axis point towards the centre
    const cv::Point2d off = distort_to_pixel(c, {0.5, 0});
    EXPECT_LT(off.x - c.cx, c.fx * 0.5);
    auto back = undistort_pixel(c, off);
    ASSERT_TRUE(back);
    EXPECT_NEAR(back->x, 0.5, 1e-9);
    EXPECT_NEAR(back->y, 0.0, 1e-9);
}

}  // namespace
}  // namespace gs
