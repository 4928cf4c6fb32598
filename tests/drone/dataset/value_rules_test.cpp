// Issue 14 points 5 and 6: every JSON reader survives every nlohmann exception (a number that
// overflows a double crashed replay with exit 134), and every CSV reader applies
// docs/dataset.md 1.1's value rules (finite numbers within physical bounds; empty = unknown),
// naming file, row, column.
#include "support/dataset_fixtures.hpp"

#include "drone/core/camera_calibration.hpp"
#include "drone/core/json_text.hpp"
#include "drone/dataset/dataset.hpp"
#include "drone/dataset/thesis.hpp"
#include "drone/dataset/value_rules.hpp"
#include "drone/dataset/writer.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <cmath>

namespace gs::value_rules_test {  // named: the drone tests are one unity build
namespace {
namespace fs = std::filesystem;
using test::TempDir;
using test::write_file;

std::string open_error(const fs::path& dir) {
    auto d = Dataset::open(dir);
    return d ? "(opened)" : to_string(d.error());
}

TEST(JsonReaders, NumberOverflowingADoubleIsRefusedNamingFileAndKey) {
    TempDir t;
    test::make_png_dataset(t.path(), 2);
    write_file(t / "flight.json", test::flight_json(64, 48, 25)
                                      .replace(test::flight_json(64, 48, 25).find("\"fps\": 25"), 9,
                                               "\"fps\": 1e400"));
    std::string e = open_error(t.path());
    EXPECT_NE(e.find("flight.json"), std::string::npos) << e;
    EXPECT_NE(e.find("'fps'"), std::string::npos) << e;
    EXPECT_NE(e.find("1e400"), std::string::npos) << e;

    test::make_png_dataset(t.path(), 2);
    write_file(t / "labels.json", R"({"scenario": "left", "obstacle": {"distance_m": 1e400}})");
    e = open_error(t.path());
    EXPECT_NE(e.find("labels.json"), std::string::npos) << e;
    EXPECT_NE(e.find("'obstacle.distance_m'"), std::string::npos) << e;

    write_file(t / "cal.json", R"({"fx": 500, "fy": 500, "cx": 1e400, "cy": 2})");
    auto c = load_calibration_file(t / "cal.json");
    ASSERT_FALSE(c);
    e = to_string(c.error());
    EXPECT_NE(e.find("cal.json"), std::string::npos) << e;
    EXPECT_NE(e.find("'cx'"), std::string::npos) << e;
}

TEST(JsonReaders, ThesisMetadataOverflowIsRefused) {
    TempDir t;
    for (int i = 0; i < 2; ++i)
        cv::imwrite((t / ("img_" + std::to_string(i) + ".png")).string(),
                    test::test_image(i, 32, 24));
    write_file(t / "imu.txt", "1 2 3 0.1 0.2\n1 2 3 0.1 0.2\n");
    ASSERT_TRUE(open_thesis_folder(t.path()));
    write_file(t / kThesisMetaFile, R"({"fps": 1e999})");
    auto d = open_thesis_folder(t.path());
    ASSERT_FALSE(d);
    const std::string e = to_string(d.error());
    EXPECT_NE(e.find(kThesisMetaFile), std::string::npos) << e;
    EXPECT_NE(e.find("'fps'"), std::string::npos) << e;
}

TEST(JsonReaders, MessagesCarryNoLibraryPrefix) {
    auto j = parse_json_text("{\"a\": tru}", "x.json");
    ASSERT_FALSE(j);
    const std::string e = to_string(j.error());
    EXPECT_EQ(e.find("[json.exception"), std::string::npos) << e;
    EXPECT_EQ(e.find("parse error at"), std::string::npos) << e;
    EXPECT_EQ(e.rfind("x.json:1:", 0), 0u) << e;
    // A type error thrown while reading values is caught at the boundary too.
    auto r = json_boundary(
        "y.json", [&]() -> Expected<int, FileError> { return nlohmann::json("text").get<int>(); });
    ASSERT_FALSE(r);
    EXPECT_EQ(to_string(r.error()).rfind("y.json: invalid value: type must be number", 0), 0u)
        << to_string(r.error());
}

struct BadCell {
    const char* column;
    const char* cell;
    const char* expect;  // what the message says after "file:line:col: column: "
};

class FramesCsvValueRules : public ::testing::TestWithParam<BadCell> {};

TEST_P(FramesCsvValueRules, RefusedNamingFileRowAndColumn) {
    const BadCell& b = GetParam();
    TempDir t;
    test::make_png_dataset(t.path(), 3);
    write_file(t / "frames.csv", std::string("frame,t_ms,roll_deg,") + b.column +
                                     "\n0,0,1,\n1,40,2," + b.cell + "\n2,80,3,\n");
    const std::string e = open_error(t.path());
    EXPECT_EQ(e.rfind(std::string("frames.csv:3:4: ") + b.column + ": " + b.expect, 0), 0u) << e;

    // navdata.csv follows the same rules (its own column order).
    test::make_png_dataset(t.path(), 3);
    write_file(t / "navdata.csv", std::string("t_ms,") + b.column + "\n0,\n5," + b.cell + "\n");
    const std::string n = open_error(t.path());
    EXPECT_EQ(n.rfind(std::string("navdata.csv:3:2: ") + b.column + ": " + b.expect, 0), 0u) << n;
}

INSTANTIATE_TEST_SUITE_P(
    DatasetMd11, FramesCsvValueRules,
    ::testing::Values(BadCell{"pitch_deg", "nan", "expected a finite number, got 'nan'"},
                      BadCell{"pitch_deg", "inf", "expected a finite number, got 'inf'"},
                      BadCell{"altitude_m", "-inf", "expected a finite number, got '-inf'"},
                      BadCell{"yaw_deg", "1e400", "'1e400' is out of the range of a double"},
                      BadCell{"pitch_deg", "1e300", "1e300 is outside [-90, 90] degrees"},
                      BadCell{"altitude_m", "-5", "-5 is outside [0, 20] m"},
                      BadCell{"altitude_m", "20.5", "20.5 is outside [0, 20] m"},
                      BadCell{"vx_mps", "-21", "-21 is outside [-20, 20] m/s"},
                      BadCell{"vz_mps", "NaN", "expected a finite number, got 'NaN'"}));

TEST(DatasetValueRules, RollOutOfBoundsInTheRequiredColumnIsRefused) {
    TempDir t;
    test::make_png_dataset(t.path(), 2);
    write_file(t / "frames.csv", "frame,t_ms,roll_deg\n0,0,1e300\n1,40,0\n");
    EXPECT_EQ(open_error(t.path()), "frames.csv:2:3: roll_deg: 1e300 is outside [-90, 90] degrees");
}

TEST(DatasetValueRules, BoundsAreInclusiveYawAndGroundTruthAnyFiniteEmptyIsUnknown) {
    TempDir t;
    test::make_png_dataset(t.path(), 3);
    write_file(t / "frames.csv",
               "frame,t_ms,roll_deg,pitch_deg,yaw_deg,vx_mps,vy_mps,vz_mps,altitude_m,gt_x_m\n"
               "0,0,90,-90,-7200,20,-20,20,0,-1e6\n"
               "1,40,-90,90,1e9,-20,20,-20,20,1e6\n"
               "2,40,,,,,,,,\n");
    auto d = Dataset::open(t.path());
    ASSERT_TRUE(d) << to_string(d.error());
    EXPECT_EQ(d->frames()[0].nav.roll_deg, 90);
    EXPECT_EQ(d->frames()[1].nav.yaw_deg, 1e9);
    EXPECT_EQ(d->frames()[1].nav.altitude_m, 20);
    EXPECT_TRUE(std::isnan(d->frames()[2].nav.roll_deg));
    EXPECT_TRUE(std::isnan(d->frames()[2].nav.altitude_m));
}

TEST(DatasetValueRules, LabelsCsvRefusesNonFiniteDistances) {
    TempDir t;
    test::make_png_dataset(t.path(), 2);
    write_file(t / "labels.csv", "frame,distance_m,lateral_m\n0,inf,0\n1,,\n");
    EXPECT_EQ(open_error(t.path()).rfind("labels.csv:2:2: distance_m: expected a finite number", 0),
              0u);
}

TEST(DatasetValueRules, ThesisImuFileRefusesInfinitiesAndAbsurdAttitude) {
    TempDir t;
    for (int i = 0; i < 2; ++i)
        cv::imwrite((t / ("img_" + std::to_string(i) + ".png")).string(),
                    test::test_image(i, 32, 24));
    write_file(t / "imu.txt", "1 2 3 0.1 0.2\nnan nan nan nan nan\n");  // nan: unknown here
    ASSERT_TRUE(open_thesis_folder(t.path()));
    write_file(t / "imu.txt", "1 2 3 0.1 0.2\n1 inf 3 0.1 0.2\n");
    auto d = open_thesis_folder(t.path());
    ASSERT_FALSE(d);
    EXPECT_EQ(to_string(d.error()), "imu.txt:2:3: expected a finite number or nan, got 'inf'");
    write_file(t / "imu.txt", "95 2 3 0.1 0.2\n1 2 3 0.1 0.2\n");
    d = open_thesis_folder(t.path());
    ASSERT_FALSE(d);
    EXPECT_EQ(to_string(d.error()), "imu.txt:1:1: roll_deg: 95 is outside [-90, 90] degrees");
}

TEST(DatasetValueRules, WriterLeavesOutWhatTheReaderWouldRefuse) {
    FrameRow r;
    r.frame = 0;
    r.nav.t_ns = 0;
    r.nav.roll_deg = 120;  // absurd: written as unknown
    r.nav.pitch_deg = 1.5;
    r.nav.altitude_m = -0.02;  // below ground
    r.nav.vx_mps = std::numeric_limits<double>::infinity();
    r.gt.x_m = 12345.5;  // any finite value is fine
    const std::string row = frames_csv_row(r);
    EXPECT_EQ(row, "0,0,,1.5,,,,,,12345.5,,,\n");
    auto rows = parse_frames_csv(frames_csv_header() + row);
    ASSERT_TRUE(rows) << to_string(rows.error());
    EXPECT_TRUE(std::isnan((*rows)[0].nav.roll_deg));
    EXPECT_EQ(writable_value("yaw_deg", 1e9), 1e9);
    EXPECT_TRUE(std::isnan(writable_value("altitude_m", 21)));
}

TEST(DatasetCutShort, NavdataCsvEndingInsideALineIsReadWithAWarning) {
    // Issue 14 point 4: a full disk left "navdata.csv:220:4: expected 12 fields, got 3" and every
    // command refused the whole flight.
    TempDir t;
    test::make_png_dataset(t.path(), 3);
    const std::string head = navdata_csv_header() + "0,1,2,3,0,0,0,1,10,0x00000001,0,80\n" +
                             "5,1,2,3,0,0,0,1,11,0x00000001,0,80\n";
    for (const std::string tail : {"10,1,2", "10,1,2,3,0,0,0,1,12,0x", "10,1,2,3,0,0,0,1,12,0"}) {
        write_file(t / "navdata.csv", head + tail);
        auto d = Dataset::open(t.path());
        ASSERT_TRUE(d) << tail << ": " << to_string(d.error());
        EXPECT_EQ(d->navdata().size(), 2u) << tail;
        bool warned = false;
        for (const auto& w : d->warnings())
            warned |= w.find("incomplete last line") != std::string::npos;
        EXPECT_TRUE(warned) << tail;
    }
    // A complete last line without its newline is kept (another tool's file).
    write_file(t / "navdata.csv", head + "10,1,2,3,0,0,0,1,12,0x00000001,0,80");
    auto d = Dataset::open(t.path());
    ASSERT_TRUE(d) << to_string(d.error());
    EXPECT_EQ(d->navdata().size(), 3u);
    // The same damage anywhere but in the last line is still an error.
    write_file(t / "navdata.csv", navdata_csv_header() + "0,1,2\n" + "5,1,2,3,0,0,0,1,11,,0,80\n");
    EXPECT_EQ(open_error(t.path()), "navdata.csv:2:4: expected 12 fields, got 3");
}

}  // namespace
}  // namespace gs::value_rules_test
