#include "support/dataset_fixtures.hpp"

#include "drone/dataset/annexb.hpp"
#include "drone/dataset/csv.hpp"
#include "drone/dataset/dataset.hpp"
#include "drone/dataset/frame_store.hpp"
#include "drone/dataset/raw.hpp"
#include "drone/dataset/raw_replay.hpp"
#include "drone/dataset/thesis.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <fstream>

namespace gs {
namespace {

using namespace dataset;
namespace fs = std::filesystem;
using test::TempDir;
using test::write_file;

std::string open_error(const fs::path& dir, const DatasetOpenOptions& o = {}) {
    auto d = Dataset::open(dir, o);
    if (d) return "(opened)";
    return to_string(d.error());
}

// Fills a stretch of the stack with a pattern: what a finished call left there is gone.
[[gnu::noinline]] int scribble_stack() {
    volatile char junk[4096];
    for (std::size_t i = 0; i < sizeof junk; ++i) junk[i] = 'Z';
    return junk[100];
}

// A csv::Table's fields are views into its text. A text short enough for std::string's inline
// buffer (15 bytes here) moved with the table changed address, and the views read what the stack
// held after Table::parse returned: "a,b\n1,2\n" read back field (0, 0) as 'I'. The smallest
// dataset CSV, raw/video_connections.csv with one connection and no final newline, is 15 bytes.
TEST(CsvTable, AShortTextKeepsItsFieldsWhenTheTableIsMovedOrCopied) {
    auto t = csv::Table::parse("a,b\n1,2\n", "x.csv");
    ASSERT_TRUE(t);
    csv::Table moved = std::move(*t);
    const csv::Table copied = moved;
    EXPECT_EQ(scribble_stack(), 'Z');
    EXPECT_EQ(moved.field(0, 0), "1");
    EXPECT_EQ(moved.field(0, 1), "2");
    EXPECT_EQ(copied.field(0, 0), "1");
    EXPECT_EQ(copied.field(0, 1), "2");
    // Through a reader: one connection at offset 0 opened at t = 9 us.
    auto c = parse_video_connections("offset,t_us\n0,9");
    ASSERT_TRUE(c) << to_string(c.error());
    ASSERT_EQ(c->size(), 1u);
    EXPECT_EQ((*c)[0].offset, 0u);
    EXPECT_EQ((*c)[0].t_us, 9);
}

TEST(DatasetReader, ReadsAPngDatasetExactly) {
    TempDir t;
    test::make_png_dataset(t.path(), 5);
    auto d = Dataset::open(t.path());
    ASSERT_TRUE(d) << to_string(d.error());
    EXPECT_EQ(d->info().width, 64);
    EXPECT_EQ(d->info().height, 48);
    EXPECT_EQ(d->info().fps, 25);
    EXPECT_EQ(d->info().camera, CameraId::Front);
    ASSERT_EQ(d->frame_count(), 5);
    EXPECT_FALSE(d->calibration_is_default());
    EXPECT_EQ(d->calibration().fx, 50.5);
    EXPECT_EQ(d->calibration().fy, 51.25);
    EXPECT_EQ(d->calibration().dist[0], -0.5);
    EXPECT_EQ(d->calibration().dist[3], 0.002);
    const FrameRow& r = d->frames()[3];
    EXPECT_EQ(r.frame, 3);
    EXPECT_EQ(r.nav.t_ns, 120'000'000);
    EXPECT_EQ(r.nav.roll_deg, 3.0);
    EXPECT_EQ(r.nav.pitch_deg, -1.5);
    EXPECT_EQ(r.nav.yaw_deg, 30.0);
    EXPECT_EQ(r.nav.altitude_m, 1.5);
    ASSERT_EQ(d->image_files().size(), 5u);
    EXPECT_EQ(d->image_files()[4].filename(), "000004.png");
    EXPECT_FALSE(d->video_path());

    auto store = open_image_frames(*d);
    ASSERT_TRUE(store);
    cv::Mat img;
    ASSERT_FALSE((*store)->read(2, img));
    EXPECT_EQ(cv::norm(img, test::test_image(2, 64, 48), cv::NORM_INF), 0.0);
}

TEST(DatasetReader, ColumnsInAnyOrderUnknownIgnoredMissingOptionalAreUnknown) {
    TempDir t;
    test::make_png_dataset(t.path(), 2);
    write_file(t / "frames.csv",
               "altitude_m,colour,roll_deg,t_ms,frame,gt_x_m\n"
               "2.5,red,-1.25,0,0,0.5\n"
               ",blue,7,33.333333,1,\n");
    auto d = Dataset::open(t.path());
    ASSERT_TRUE(d) << to_string(d.error());
    const auto& r0 = d->frames()[0];
    const auto& r1 = d->frames()[1];
    EXPECT_EQ(r0.nav.roll_deg, -1.25);
    EXPECT_EQ(r0.nav.altitude_m, 2.5);
    EXPECT_EQ(r0.gt.x_m, 0.5);
    EXPECT_EQ(r1.nav.t_ns, 33'333'333);
    EXPECT_EQ(r1.nav.roll_deg, 7.0);
    // absent columns and empty fields are unknown, never zero
    EXPECT_TRUE(std::isnan(r0.nav.pitch_deg));
    EXPECT_TRUE(std::isnan(r0.nav.vx_mps));
    EXPECT_TRUE(std::isnan(r0.gt.yaw_deg));
    EXPECT_TRUE(std::isnan(r1.nav.altitude_m));
    EXPECT_TRUE(std::isnan(r1.gt.x_m));
}

TEST(DatasetReader, CrlfAndBlankLinesAccepted) {
    TempDir t;
    test::make_png_dataset(t.path(), 2);
    write_file(t / "frames.csv", "frame,t_ms,roll_deg\r\n0,0,1\r\n\r\n1,40,2\r\n\r\n");
    auto d = Dataset::open(t.path());
    ASSERT_TRUE(d) << to_string(d.error());
    EXPECT_EQ(d->frames()[1].nav.roll_deg, 2.0);
}

TEST(DatasetReader, MissingFilesAreNamed) {
    TempDir t;
    test::make_png_dataset(t.path(), 2);
    fs::remove(t / "flight.json");
    EXPECT_EQ(open_error(t.path()), "flight.json: file not found");
    test::make_png_dataset(t.path(), 2);
    fs::remove(t / "frames.csv");
    EXPECT_EQ(open_error(t.path()), "frames.csv: file not found");
    test::make_png_dataset(t.path(), 2);
    fs::remove_all(t / "frames");
    EXPECT_EQ(open_error(t.path()),
              "flight.json: neither 'video.h264' nor 'frames/' is present in the dataset");
}

TEST(DatasetReader, MissingRequiredKeyOrColumn) {
    TempDir t;
    test::make_png_dataset(t.path(), 2);
    write_file(
        t / "flight.json",
        R"({"format": "ardrone-dataset", "version": 1, "camera": "front", "width": 64, "height": 48})");
    EXPECT_EQ(open_error(t.path()), "flight.json: missing required key 'fps'");

    test::make_png_dataset(t.path(), 2);
    write_file(t / "frames.csv", "frame,t_ms,pitch_deg\n0,0,1\n1,40,2\n");
    EXPECT_EQ(open_error(t.path()), "frames.csv:1: missing required column 'roll_deg'");
}

TEST(DatasetReader, BadNumberNamesLineAndColumn) {
    TempDir t;
    test::make_png_dataset(t.path(), 3);
    write_file(t / "frames.csv", "frame,t_ms,roll_deg\n0,0,1\n1,40,abc\n2,80,3\n");
    EXPECT_EQ(open_error(t.path()), "frames.csv:3:3: roll_deg: expected a number, got 'abc'");
    write_file(t / "frames.csv", "frame,t_ms,roll_deg\n0,0,1\n1,40,2\n2,80,3,4\n");
    EXPECT_EQ(open_error(t.path()), "frames.csv:4:4: expected 3 fields, got 4");
    write_file(t / "frames.csv", "frame,t_ms,roll_deg\n0,0,1\n2,40,2\n2,80,3\n");
    EXPECT_EQ(
        open_error(t.path()),
        "frames.csv:3:1: frame: expected frame 1, got 2 (rows are frames 0, 1, 2 ... in order)");
    write_file(t / "frames.csv", "frame,t_ms,roll_deg\n0,0,1\n1,40,2\n2,39.5,3\n");
    EXPECT_EQ(open_error(t.path()), "frames.csv:4:2: t_ms: time goes backwards (39.5 after 40)");
}

TEST(DatasetReader, BadJsonNamesLineAndColumn) {
    TempDir t;
    test::make_png_dataset(t.path(), 2);
    write_file(t / "flight.json", "{\n  \"format\": \"ardrone-dataset\",\n  \"version\": 1,,\n}\n");
    const std::string e = open_error(t.path());
    EXPECT_EQ(e.rfind("flight.json:3:16: invalid JSON", 0), 0u) << e;
    write_file(t / "flight.json",
               test::flight_json(64, 48, 25)
                   .replace(test::flight_json(64, 48, 25).find("\"front\""), 7, "\"side\""));
    EXPECT_EQ(open_error(t.path()),
              "flight.json:4:3: 'camera': expected \"front\" or \"bottom\", got \"side\"");
}

TEST(DatasetReader, RowCountMustMatchImagesAndDeclaredFrames) {
    TempDir t;
    test::make_png_dataset(t.path(), 4);
    fs::remove(t / "frames/000002.png");
    EXPECT_EQ(open_error(t.path()),
              "frames/: holds 3 of the 4 frames in frames.csv; frame 2 (000002.png or .jpg) is "
              "missing");
    test::make_png_dataset(t.path(), 4);
    write_file(t / "flight.json", test::flight_json(64, 48, 25, "\"frames\": 5"));
    EXPECT_EQ(open_error(t.path()), "flight.json:8:3: 'frames' is 5 but frames.csv has 4 rows");
    // More images than rows (a killed recording): readable, with a warning.
    test::make_png_dataset(t.path(), 4);
    write_file(t / "frames.csv", "frame,t_ms,roll_deg\n0,0,1\n1,40,2\n");
    write_file(t / "flight.json",
               test::flight_json(64, 48, 25,
                                 "\"calibration\": {\"fx\": 1, \"fy\": 1, \"cx\": 0, \"cy\": 0}"));
    auto d = Dataset::open(t.path());
    ASSERT_TRUE(d) << to_string(d.error());
    EXPECT_EQ(d->image_files().size(), 2u);
    ASSERT_EQ(d->warnings().size(), 1u);
    EXPECT_EQ(d->warnings()[0], "frames/: 2 images after the last frames.csv row are ignored");
}

TEST(DatasetReader, PathsInMetadataStayInsideTheDataset) {
    TempDir t;
    test::make_png_dataset(t.path() / "d", 2);
    const auto dir = t.path() / "d";
    const std::string cal = "\"calibration\": {\"fx\": 1, \"fy\": 1, \"cx\": 0, \"cy\": 0}";
    write_file(dir / "flight.json", test::flight_json(64, 48, 25, "\"video\": \"../x.h264\""));
    EXPECT_EQ(open_error(dir),
              "flight.json:8:3: 'video': must be a relative path inside the dataset, got "
              "'../x.h264'");
    write_file(dir / "flight.json",
               test::flight_json(64, 48, 25, "\"images\": \"frames/../../d/frames\""));
    EXPECT_EQ(open_error(dir).find("flight.json:8:3: 'images': must be a relative path"), 0u);
    write_file(dir / "flight.json", test::flight_json(64, 48, 25, "\"images\": \"/etc\""));
    EXPECT_EQ(open_error(dir).find("flight.json:8:3: 'images': must be a relative path"), 0u);
    // A symlink that leads out of the dataset is refused too.
    test::make_png_dataset(t.path() / "outside", 2);
    fs::create_directory_symlink(t.path() / "outside/frames", dir / "escape");
    write_file(dir / "flight.json",
               test::flight_json(64, 48, 25, cal + ", \"images\": \"escape\""));
    EXPECT_EQ(open_error(dir),
              "flight.json: 'images' (escape) resolves outside the dataset directory");
}

TEST(DatasetReader, FixedNameFilesThatLinkOutsideAreRefused) {
    // flight.json, frames.csv, navdata.csv, labels.*, video.h264 and raw/ have fixed names; a
    // symlink in their place that leads out of the dataset is refused, naming the file.
    TempDir t;
    test::make_png_dataset(t / "outside", 2);
    write_file(t / "outside/secret.csv", "frame,t_ms,roll_deg\n0,0,0\n1,40,0\n");
    fs::create_directories(t / "outside/rawdir");
    for (const std::string name : {"flight.json", "frames.csv", "navdata.csv", "labels.json",
                                   "labels.csv", "video.h264", "raw"}) {
        SCOPED_TRACE(name);
        const fs::path dir = t / ("d_" + name);
        test::make_png_dataset(dir, 2);
        fs::remove(dir / name);
        if (name == "raw")
            fs::create_directory_symlink(t / "outside/rawdir", dir / name);
        else if (name == "flight.json")
            fs::create_symlink(t / "outside/flight.json", dir / name);
        else
            fs::create_symlink(t / "outside/secret.csv", dir / name);
        const std::string e = open_error(dir);
        EXPECT_NE(e.find(name), std::string::npos) << e;
        EXPECT_NE(e.find("resolves outside the dataset directory"), std::string::npos) << e;
    }
    // A link that stays inside is fine.
    const fs::path ok = t / "inside";
    test::make_png_dataset(ok, 2);
    write_file(ok / "meta/labels.json", R"({"scenario": "left"})");
    fs::create_symlink("meta/labels.json", ok / "labels.json");
    auto d = Dataset::open(ok);
    ASSERT_TRUE(d) << to_string(d.error());
    ASSERT_TRUE(d->labels());
    EXPECT_EQ(d->labels()->scenario, Scenario::Left);
}

TEST(DatasetReader, RawFilesThatLinkOutsideAreRefused) {
    TempDir t;
    write_file(t / "outside/at.log", "0 AT*REF=1,290717696\r\n");
    const fs::path dir = t / "d";
    test::make_png_dataset(dir, 2);
    fs::create_directories(dir / "raw");
    fs::create_symlink(t / "outside/at.log", dir / "raw/at.log");
    auto d = Dataset::open(dir);
    ASSERT_TRUE(d) << to_string(d.error());
    ASSERT_TRUE(d->raw_dir());
    auto at = read_at_log(*d->raw_dir());
    ASSERT_FALSE(at);
    EXPECT_EQ(at.error().code, FileErrorCode::UnsafePath);
    EXPECT_NE(to_string(at.error()).find("raw/at.log"), std::string::npos) << to_string(at.error());
    // The thesis layout's IMU file too.
    const fs::path thesis = t / "thesis";
    write_file(t / "outside/imu.txt", "0 0 0 0 0\n");
    fs::create_directories(thesis);
    cv::imwrite((thesis / "a.png").string(), test::test_image(0, 64, 48));
    fs::create_symlink(t / "outside/imu.txt", thesis / "imu.txt");
    auto th = open_thesis_folder(thesis);
    ASSERT_FALSE(th);
    EXPECT_NE(to_string(th.error()).find("imu.txt: resolves outside the dataset directory"),
              std::string::npos)
        << to_string(th.error());
}

TEST(DatasetReader, AbsurdValuesAreRefused) {
    TempDir t;
    test::make_png_dataset(t.path(), 2);
    write_file(t / "flight.json", test::flight_json(100000, 48, 25));
    EXPECT_EQ(open_error(t.path()), "flight.json:5:3: 'width': 100000 is out of range [1, 8192]");
    write_file(t / "flight.json", test::flight_json(64, -3, 25));
    EXPECT_EQ(open_error(t.path()), "flight.json:6:3: 'height': -3 is out of range [1, 8192]");
    write_file(t / "flight.json", test::flight_json(64, 48, 0));
    EXPECT_EQ(open_error(t.path()), "flight.json:7:3: 'fps': 0 is out of range (0, 1000]");
    write_file(t / "flight.json", test::flight_json(64, 48, 1e9));
    EXPECT_EQ(open_error(t.path()), "flight.json:7:3: 'fps': 1e+09 is out of range (0, 1000]");
    write_file(t / "flight.json", test::flight_json(64, 48, 25, "\"frames\": 99999999999"));
    EXPECT_EQ(open_error(t.path()),
              "flight.json:8:3: 'frames': 99999999999 is out of range [0, 10000000]");
    // a file far larger than a flight.json can be is not read into memory
    DatasetOpenOptions small;
    small.limits.max_json_bytes = 64;
    write_file(t / "flight.json", test::flight_json(64, 48, 25));
    EXPECT_EQ(open_error(t.path(), small).find("flight.json: file is "), 0u);
}

TEST(DatasetReader, VersionAndFormatChecked) {
    TempDir t;
    test::make_png_dataset(t.path(), 2);
    std::string j = test::flight_json(64, 48, 25);
    j.replace(j.find("\"version\": 1"), 12, "\"version\": 2");
    write_file(t / "flight.json", j);
    EXPECT_EQ(
        open_error(t.path()),
        "flight.json:3:3: 'version': version 2 is not supported (this reader knows version 1)");
}

TEST(DatasetReader, DefaultCalibrationFromAssetsScaledToFrameSize) {
    TempDir t;
    test::make_png_dataset(t.path() / "d", 2, 320, 180);
    write_file(t.path() / "d/flight.json", test::flight_json(320, 180, 25));
    test::make_assets(t.path() / "assets");
    DatasetOpenOptions o;
    o.assets_dir = t.path() / "assets";
    auto d = Dataset::open(t.path() / "d", o);
    ASSERT_TRUE(d) << to_string(d.error());
    EXPECT_TRUE(d->calibration_is_default());
    EXPECT_EQ(d->calibration().fx, 280.0);
    EXPECT_EQ(d->calibration().cx, 159.5);  // (319.5 + 0.5) / 2 - 0.5
    EXPECT_EQ(d->calibration().dist[0], -0.5);
    EXPECT_EQ(d->calibration().width, 320);
    // without any calibration the error names the missing default
    o.assets_dir = t.path() / "nowhere";
    const std::string e = open_error(t.path() / "d", o);
    EXPECT_NE(e.find("ardrone2_front.json: no calibration in flight.json and the default failed: "
                     "file not found"),
              std::string::npos)
        << e;
}

TEST(DatasetReader, ShippedDefaultCalibrationLoadsWhenPresent) {
    const fs::path f = fs::path(GS_ASSETS_DIR) / "calibration/ardrone2_front.json";
    if (!fs::exists(f)) GTEST_SKIP() << f << " not in this tree yet";
    auto c = default_calibration(CameraId::Front, GS_ASSETS_DIR);
    ASSERT_TRUE(c) << to_string(c.error());
    EXPECT_GT(c->fx, 0);
}

TEST(DatasetReader, NavdataAndLabels) {
    TempDir t;
    test::make_png_dataset(t.path(), 3);
    write_file(t / "navdata.csv",
               "t_ms,roll_deg,seq,state,ctrl_state,battery_pct,mystery\n"
               "0,1.5,10,0x0480C050,262144,87,x\n"
               "5,,11,0x0480C051,0x40000,86.5,y\n");
    write_file(t / "labels.json", R"({"scenario": "left", "obstacle": "pillar 4"})");
    write_file(t / "labels.csv", "frame,distance_m,lateral_m\n0,3.5,-0.25\n1,,\n");
    auto d = Dataset::open(t.path());
    ASSERT_TRUE(d) << to_string(d.error());
    ASSERT_TRUE(d->has_navdata());
    ASSERT_EQ(d->navdata().size(), 2u);
    EXPECT_EQ(d->navdata()[0].roll_deg, 1.5);
    EXPECT_EQ(*d->navdata()[0].seq, 10u);
    EXPECT_EQ(*d->navdata()[0].drone_state, 0x0480C050u);
    EXPECT_EQ(*d->navdata()[1].ctrl_state, 0x40000u);
    EXPECT_EQ(d->navdata()[1].battery_pct, 86.5);
    EXPECT_TRUE(std::isnan(d->navdata()[1].roll_deg));
    EXPECT_TRUE(std::isnan(d->navdata()[0].altitude_m));
    ASSERT_TRUE(d->labels());
    EXPECT_EQ(d->labels()->scenario, Scenario::Left);
    ASSERT_TRUE(d->label_rows());
    EXPECT_EQ((*d->label_rows())[0].lateral_m, -0.25);
    EXPECT_TRUE(std::isnan((*d->label_rows())[1].distance_m));

    write_file(t / "navdata.csv", "t_ms,state\n0,1234\n");
    EXPECT_EQ(open_error(t.path()),
              "navdata.csv:2:2: state: expected 0x-prefixed hexadecimal, got '1234'");
    fs::remove(t / "navdata.csv");
    write_file(t / "labels.json", R"({"scenario": "up"})");
    EXPECT_EQ(open_error(t.path()),
              "labels.json:1:2: 'scenario': expected left, right, center or none, got \"up\"");
}

TEST(DatasetReader, CorruptImageIsReportedWhenRead) {
    TempDir t;
    test::make_png_dataset(t.path(), 2);
    write_file(t / "frames/000001.png", "not a png at all");
    auto d = Dataset::open(t.path());
    ASSERT_TRUE(d);
    auto store = open_image_frames(*d);
    ASSERT_TRUE(store);
    cv::Mat img;
    auto e = (*store)->read(1, img);
    ASSERT_TRUE(e);
    EXPECT_EQ(to_string(*e), "frames/000001.png: not a decodable PNG/JPEG image");
    cv::imwrite((t / "frames/000001.png").string(), test::test_image(1, 32, 48));
    e = (*store)->read(1, img);
    ASSERT_TRUE(e);
    EXPECT_EQ(to_string(*e), "frames/000001.png: image is 32x48, flight.json says 64x48");
}

void write_video(const fs::path& p, int n) {
    std::ofstream out(p, std::ios::binary);
    for (int i = 0; i < n; ++i) {
        auto au = test::fake_access_unit(i % 5 == 0, 100 + i, static_cast<std::uint8_t>(i));
        out.write(reinterpret_cast<const char*>(au.data()),
                  static_cast<std::streamsize>(au.size()));
    }
}

TEST(DatasetReader, VideoIsIndexedAndATruncatedOneRefused) {
    TempDir t;
    test::make_png_dataset(t.path(), 6);
    write_video(t / "video.h264", 6);
    auto d = Dataset::open(t.path());
    ASSERT_TRUE(d) << to_string(d.error());
    ASSERT_TRUE(d->video_path());
    ASSERT_EQ(d->video_units().size(), 6u);
    EXPECT_EQ(d->video_units()[0].offset, 0u);
    EXPECT_EQ(d->video_units()[0].size, 106u);
    EXPECT_TRUE(d->video_units()[5].idr);
    EXPECT_FALSE(d->video_units()[4].idr);
    EXPECT_EQ(d->video_units()[5].offset, 106u + 107 + 108 + 109 + 110);

    const auto full = fs::file_size(t / "video.h264");
    fs::resize_file(t / "video.h264", full - 120);  // cut into access unit 4
    EXPECT_EQ(open_error(t.path()),
              "video.h264: holds 5 access units but frames.csv has 6 rows (truncated?)");
}

TEST(AnnexB, SplitsOnAudParameterSetsAndFirstSlice) {
    // AUD, SPS, PPS, IDR slice (2 slices: first_mb 0 then non-zero), then a P slice AU.
    const std::vector<std::uint8_t> s = {
        0, 0, 0, 1,    0x09, 0xF0,        // AUD
        0, 0, 0, 1,    0x67, 0x42, 0x00,  // SPS
        0, 0, 1, 0x68, 0xCE,              // PPS
        0, 0, 1, 0x65, 0x88, 0x84,        // IDR slice, first_mb = 0
        0, 0, 1, 0x65, 0x40, 0x11,        // IDR slice, first_mb != 0 (same picture)
        0, 0, 0, 1,    0x41, 0x9A, 0x22,  // P slice, first_mb = 0: new AU
        0, 0, 1, 0x41, 0x9A};
    auto units = split_access_units(s);
    ASSERT_EQ(units.size(), 3u);
    EXPECT_EQ(units[0].offset, 0u);
    EXPECT_EQ(units[0].size, 30u);
    EXPECT_TRUE(units[0].idr);
    EXPECT_EQ(units[1].offset, 30u);
    EXPECT_EQ(units[1].size, 7u);
    EXPECT_FALSE(units[1].idr);
    EXPECT_EQ(units[2].size, 5u);
    // Any chunking gives the same units.
    AnnexBScanner sc;
    for (std::size_t i = 0; i < s.size(); ++i) sc.feed(std::span(&s[i], 1));
    sc.finish();
    ASSERT_EQ(sc.units().size(), 3u);
    EXPECT_EQ(sc.units()[1].offset, 30u);
    EXPECT_TRUE(annexb_has_idr(std::span(s).subspan(0, 30)));
    EXPECT_FALSE(annexb_has_idr(std::span(s).subspan(30)));
}

TEST(AnnexB, RealPaveCaptureHasPictures) {
    // node-ar-drone_pave.bin is PaVE-framed H.264 from a real drone: the H.264 inside still
    // splits into pictures with IDRs (PaVE headers are junk between NALs to this scanner).
    const fs::path f = fs::path(GS_FIXTURES_DIR) / "ardrone/node-ar-drone_pave.bin";
    if (!fs::exists(f)) GTEST_SKIP() << "fixture missing";
    const std::string bytes = test::read_file(f);
    auto units = split_access_units(
        std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
    EXPECT_GT(units.size(), 1u);
    bool any_idr = false;
    for (const auto& u : units) any_idr = any_idr || u.idr;
    EXPECT_TRUE(any_idr);
}

}  // namespace
}  // namespace gs
