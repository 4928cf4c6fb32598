// drone/core/camera_calibration: the one calibration record and its file codec: JSON in the
// flight.json / assets / `calibrate` shape, save and load round trip with the notes, whole
// flight.json files, defaults from assets, scaling, and the distortion helpers.

#include "drone/core/camera_calibration.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
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
    EXPECT_EQ(a.error().code, FileErrorCode::Missing);
    auto b = parse(R"({"fx": -1, "fy": 1, "cx": 0, "cy": 0})");
    ASSERT_FALSE(b);
    EXPECT_EQ(b.error().code, FileErrorCode::OutOfRange);
    auto d = parse(R"({"fx": 1, "fy": 1, "cx": 0, "cy": 0, "dist": [1, 2, 3]})");
    ASSERT_FALSE(d);
    EXPECT_EQ(d.error().key, "dist");
    auto w = parse(R"({"fx": 1, "fy": 1, "cx": 0, "cy": 0, "width": 640})");
    ASSERT_FALSE(w);
    EXPECT_EQ(w.error().key, "height");
    auto s = parse(R"({"fx": 1, "fy": 1, "cx": "0", "cy": 0})");
    ASSERT_FALSE(s);
    EXPECT_EQ(s.error().key, "cx");
    EXPECT_EQ(s.error().code, FileErrorCode::Malformed);
}

TEST(Calibration, AStatedRollingShutterReadoutRoundTripsAndIsChecked) {
    // readout_ms: part of the camera model, so written in flight.json's shape too (without the
    // extras) when known, and left out when not (NaN is not JSON).
    auto c = calibration_from_json(
        nlohmann::json::parse(R"({"fx": 570, "fy": 568, "cx": 331, "cy": 136, "readout_ms": 25})"));
    ASSERT_TRUE(c);
    EXPECT_EQ(c->readout_ms, 25.0);
    for (bool extras : {false, true}) {
        const nlohmann::json j = calibration_to_json(*c, extras);
        EXPECT_EQ(j.at("readout_ms"), 25.0) << extras;
        auto back = calibration_from_json(j);
        ASSERT_TRUE(back);
        EXPECT_EQ(back->readout_ms, 25.0);
    }
    auto global = calibration_from_json(
        nlohmann::json::parse(R"({"fx": 570, "fy": 568, "cx": 331, "cy": 136, "readout_ms": 0})"));
    ASSERT_TRUE(global);
    EXPECT_EQ(global->readout_ms, 0.0);
    EXPECT_EQ(global->scaled_to(320, 180).readout_ms, 0.0);
    auto unstated = calibration_from_json(
        nlohmann::json::parse(R"({"fx": 570, "fy": 568, "cx": 331, "cy": 136})"));
    ASSERT_TRUE(unstated);
    EXPECT_TRUE(std::isnan(unstated->readout_ms));
    EXPECT_FALSE(calibration_to_json(*unstated, true).contains("readout_ms"));
    for (const char* bad : {R"({"fx": 1, "fy": 1, "cx": 0, "cy": 0, "readout_ms": -3})",
                            R"({"fx": 1, "fy": 1, "cx": 0, "cy": 0, "readout_ms": 5000})",
                            R"({"fx": 1, "fy": 1, "cx": 0, "cy": 0, "readout_ms": "25"})"}) {
        auto r = calibration_from_json(nlohmann::json::parse(bad));
        ASSERT_FALSE(r) << bad;
        EXPECT_EQ(r.error().key, "readout_ms") << bad;
    }
}

TEST(Calibration, SaveLoadRoundTrip) {
    TempFile f("cam.json");
    CameraCalibration c = builtin_calibration(CameraId::Front);
    c.source = "test \"quoted\"";
    auto saved = save_calibration_file(f.path, c);
    ASSERT_TRUE(saved) << to_string(saved.error());
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

TEST(Calibration, NotesRoundTripAndUnknownNotesStayUnknown) {
    TempFile f("notes.json");
    CameraCalibration c = builtin_calibration(CameraId::Bottom);
    CalibrationInfo info;
    info.camera = "bottom";
    info.rms_px = 0.31;
    info.std_dev = {1.5, 1.25, 0.5, 0.75, 0.01, 0.02, kUnknown, 0.004, kUnknown};
    info.views = 17;
    ASSERT_TRUE(save_calibration_file(f.path, c, info));
    auto back = load_calibration_document(f.path);
    ASSERT_TRUE(back) << to_string(back.error());
    EXPECT_EQ(back->camera.fx, c.fx);
    EXPECT_EQ(back->camera.source, c.source);
    EXPECT_EQ(back->info.camera, "bottom");
    EXPECT_EQ(back->info.rms_px, 0.31);
    EXPECT_EQ(back->info.views, 17);
    EXPECT_EQ(back->info.std_dev[0], 1.5);
    EXPECT_EQ(back->info.std_dev[7], 0.004);
    EXPECT_FALSE(known(back->info.std_dev[6]));  // written as null, read back as unknown
    EXPECT_FALSE(known(back->info.std_dev[8]));
    // Without notes nothing unknown is written.
    TempFile g("plain.json");
    ASSERT_TRUE(save_calibration_file(g.path, c));
    auto plain = load_calibration_document(g.path);
    ASSERT_TRUE(plain);
    EXPECT_FALSE(known(plain->info.rms_px));
    EXPECT_EQ(plain->info.views, 0);
    EXPECT_TRUE(plain->info.camera.empty());
}

TEST(Calibration, ReadsAWholeFlightJson) {
    // docs/dataset.md's example flight.json: the size is at the top level.
    const char* flight = R"({ "format": "ardrone-dataset", "version": 1, "camera": "front",
      "width": 640, "height": 360, "fps": 30, "frames": 190,
      "calibration": { "fx": 571.37, "fy": 569.36, "cx": 329.85, "cy": 177.76,
                       "dist": [-0.5176, 0.2687, 0.0001, 0.0013, 0.0] },
      "source": "recorded" })";
    auto d = parse_calibration(flight, "flight.json");
    ASSERT_TRUE(d) << to_string(d.error());
    EXPECT_EQ(d->camera.width, 640);
    EXPECT_EQ(d->camera.height, 360);
    EXPECT_DOUBLE_EQ(d->camera.fx, 571.37);
    EXPECT_DOUBLE_EQ(d->camera.dist[1], 0.2687);
    EXPECT_EQ(d->info.camera, "front");
    // A 4-coefficient file: k3 = 0.
    auto four = parse_calibration(
        R"({"width":640,"height":360,"fx":1,"fy":1,"cx":0,"cy":0,"dist":[0.1,0.2,0.3,0.4]})",
        "four.json");
    ASSERT_TRUE(four);
    EXPECT_DOUBLE_EQ(four->camera.dist[3], 0.4);
    EXPECT_DOUBLE_EQ(four->camera.dist[4], 0.0);
    // A bad key inside flight.json's object is named with its path.
    auto bad = parse_calibration(R"({"width": 640, "height": 360,
      "calibration": {"fx": -1, "fy": 1, "cx": 0, "cy": 0}})",
                                 "flight.json");
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().code, FileErrorCode::OutOfRange);
    EXPECT_EQ(to_string(bad.error()),
              "flight.json:2:23: 'calibration.fx': focal lengths must be positive");
}

TEST(Calibration, BadTextsGiveTypedErrors) {
    auto code = [](const char* text) {
        auto r = parse_calibration(text, "c.json");
        return r ? std::string("ok") : to_string(r.error().code);
    };
    const std::string malformed = to_string(FileErrorCode::Malformed);
    EXPECT_EQ(code("{"), malformed);
    EXPECT_EQ(code("[1,2]"), malformed);
    EXPECT_EQ(code(R"({"width":640,"height":360,"fy":1,"cx":0,"cy":0,"dist":[0,0,0,0,0]})"),
              to_string(FileErrorCode::Missing));  // no fx
    EXPECT_EQ(code(R"({"width":640,"height":360,"fx":1,"fy":1,"cx":0,"cy":0,"dist":[0,0,0]})"),
              malformed);
    EXPECT_EQ(code(R"({"width":640,"height":360,"fx":-5,"fy":1,"cx":0,"cy":0,"dist":[0,0,0,0,0]})"),
              to_string(FileErrorCode::OutOfRange));
    EXPECT_EQ(code(R"({"width":64.5,"height":360,"fx":5,"fy":1,"cx":0,"cy":0,"dist":[0,0,0,0,0]})"),
              malformed);
    // The size is optional (the flight's), but never half of it.
    EXPECT_EQ(code(R"({"fx":1,"fy":1,"cx":0,"cy":0,"dist":[0,0,0,0,0]})"), "ok");
    EXPECT_EQ(code(R"({"width":640,"fx":1,"fy":1,"cx":0,"cy":0})"),
              to_string(FileErrorCode::Missing));
    // Saving refuses an invalid calibration and reports a directory it cannot write.
    EXPECT_FALSE(save_calibration_file("/tmp/gs_never_written.json", CameraCalibration{}));
    auto unwritable =
        save_calibration_file("/nonexistent/dir/x.json", builtin_calibration(CameraId::Front));
    ASSERT_FALSE(unwritable);
    EXPECT_EQ(unwritable.error().code, FileErrorCode::Io);
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
    EXPECT_EQ(missing.error().code, FileErrorCode::Missing);
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
    const CameraCalibration h = c.scaled_to(320, 180);
    EXPECT_EQ(h.fx, 280);
    EXPECT_EQ(h.fy, 250);
    EXPECT_EQ(h.cx, 159.5);  // (319.5 + 0.5) / 2 - 0.5: still the image centre
    EXPECT_EQ(h.cy, 89.5);
    EXPECT_EQ(h.dist, c.dist);
    EXPECT_EQ(h.width, 320);
    // an unknown source size is taken as the target size
    c.width = c.height = 0;
    const CameraCalibration u = c.scaled_to(320, 180);
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

TEST(Calibration, ProjectIsThePinholeWithoutDistortion) {
    CameraCalibration c = builtin_calibration(CameraId::Front);
    // straight ahead: the principal point, whatever the direction's length
    EXPECT_EQ(c.project({0, 0, 1}), cv::Point2d(c.cx, c.cy));
    EXPECT_EQ(c.project({0, 0, 7}), cv::Point2d(c.cx, c.cy));
    // one unit right and two down per four ahead: fx / 4 right, fy / 2 down, without distortion
    const cv::Point2d p = c.project({2, 4, 8});
    EXPECT_DOUBLE_EQ(p.x, c.cx + c.fx * 0.25);
    EXPECT_DOUBLE_EQ(p.y, c.cy + c.fy * 0.5);
    // the same direction from the other side of the camera lands mirrored about the centre
    const cv::Point2d m = c.project({-2, -4, 8});
    EXPECT_DOUBLE_EQ(m.x - c.cx, c.cx - p.x);
    EXPECT_DOUBLE_EQ(m.y - c.cy, c.cy - p.y);
}

}  // namespace
}  // namespace gs
