// `ardrone-gs calibrate` run as a process (GS_BINARY) on the real rjw57 chessboard frames and on
// bad input built in /tmp: success writes flight.json's calibration shape; failures exit non-zero
// with a reason and write no file.
#include "cli_test_util.hpp"
#include "drone/video/h264_encoder.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;

using gs::test::CmdResult;

const std::string kFrames =
    std::string(GS_FIXTURES_DIR) + "/real/calibration/rjw57_ardrone2_front_chessboard";

std::string frame(int i) {
    char name[32];
    std::snprintf(name, sizeof name, "/frame%04d.jpg", i);
    return kFrames + name;
}

fs::path scratch(const std::string& name) {
    return gs::test::scratch_dir("calibrate_test", name);
}

TEST(CalibrateCli, RealFramesWriteACalibration) {
    const fs::path dir = scratch("ok");
    const fs::path out = dir / "front.json";
    const CmdResult r = gs::test::run_cli(
        "calibrate " + kFrames + " --board 9x6 --square 0.05 --camera front --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    // Progress per image, the report and the file.
    EXPECT_NE(r.out.find("[11/11] frame0010.jpg"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("Overall RMS"), std::string::npos);
    EXPECT_NE(r.out.find("fx "), std::string::npos);
    EXPECT_NE(r.out.find("Coverage"), std::string::npos);
    std::ifstream in(out);
    ASSERT_TRUE(in.good());
    const auto j = nlohmann::json::parse(in);
    EXPECT_NEAR(j["fx"].get<double>(), 568.0, 10.0);
    EXPECT_NEAR(j["fy"].get<double>(), 566.0, 10.0);
    EXPECT_NEAR(j["cx"].get<double>(), 320.0, 10.0);
    EXPECT_NEAR(j["cy"].get<double>(), 178.0, 10.0);
    EXPECT_EQ(j["width"], 640);
    EXPECT_EQ(j["height"], 360);
    EXPECT_EQ(j["dist"].size(), 5U);
    EXPECT_LT(j["rms_px"].get<double>(), 0.3);
    EXPECT_GT(j["std_dev"]["fx"].get<double>(), 0.0);
    EXPECT_EQ(j["views"], 11);
    EXPECT_EQ(j["camera"], "front");
    EXPECT_FALSE(fs::exists(out.string() + ".tmp"));
}

TEST(CalibrateCli, DatasetFramesWithStep) {
    // A recorded dataset: flight.json + frames/ (docs/dataset.md); every 2nd frame -> 6 of 11.
    const fs::path ds = scratch("dataset");
    fs::create_directories(ds / "frames");
    for (int i = 0; i < 11; ++i) {
        char name[32];
        std::snprintf(name, sizeof name, "%06d.jpg", i);
        fs::copy_file(frame(i), ds / "frames" / name);
    }
    std::ofstream(ds / "flight.json") << R"({"format":"ardrone-dataset","version":1,
        "camera":"front","width":640,"height":360,"fps":30,"images":"frames"})";
    std::ofstream csv(ds / "frames.csv");
    csv << "frame,t_ms,roll_deg\n";
    for (int i = 0; i < 11; ++i) csv << i << ',' << i * 100 << ",0\n";
    csv.close();
    const fs::path out = ds / "cal.json";
    const CmdResult r = gs::test::run_cli(
        "calibrate " + ds.string() + " --step 2 --board 9x6 --square 0.05 --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("from 6 image(s)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("frames/000010.jpg"), std::string::npos) << r.out;
    const auto j = nlohmann::json::parse(std::ifstream(out));
    EXPECT_EQ(j["views"], 6);
    EXPECT_EQ(j["camera"], "front");  // taken from flight.json
    EXPECT_NEAR(j["fx"].get<double>(), 568.0, 15.0);
}

TEST(CalibrateCli, VideoOnlyDatasetIsDecodedThroughTheDatasetReader) {
    // A recorded dataset holding only video.h264 (as `record` writes): the 11 real frames encoded
    // as H.264, read back through the dataset reader and decoded; --step 2 takes 6 of them.
    const fs::path ds = scratch("video_only");
    gs::video::H264EncoderConfig ec;
    ec.bitrate_bps = 8'000'000;  // the corners must survive the encoding
    auto enc = gs::video::H264Encoder::create(ec);
    ASSERT_TRUE(enc.has_value()) << gs::video::to_string(enc.error());
    std::ofstream video(ds / "video.h264", std::ios::binary);
    std::ofstream csv(ds / "frames.csv");
    csv << "frame,t_ms,roll_deg\n";
    std::vector<std::uint8_t> au;
    for (int i = 0; i < 11; ++i) {
        bool idr = false;
        const cv::Mat img = cv::imread(frame(i), cv::IMREAD_COLOR);
        ASSERT_EQ(img.size(), cv::Size(640, 360));
        ASSERT_TRUE((*enc)->encode(img, au, idr).has_value());
        video.write(reinterpret_cast<const char*>(au.data()),
                    static_cast<std::streamsize>(au.size()));
        csv << i << ',' << i * 100 << ",0\n";
    }
    video.close();
    csv.close();
    std::ofstream(ds / "flight.json") << R"({"format":"ardrone-dataset","version":1,
        "camera":"front","width":640,"height":360,"fps":30})";
    const fs::path out = ds / "cal.json";
    const CmdResult r = gs::test::run_cli(
        "calibrate " + ds.string() + " --step 2 --board 9x6 --square 0.05 --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("from 6 image(s)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("video.h264 frame 10"), std::string::npos) << r.out;
    const auto j = nlohmann::json::parse(std::ifstream(out));
    EXPECT_EQ(j["views"], 6);
    EXPECT_EQ(j["camera"], "front");
    EXPECT_NEAR(j["fx"].get<double>(), 568.0, 15.0);
}

TEST(CalibrateCli, DatasetOutsideTheRulesIsRefused) {
    // The dataset reader's rules apply: without frames.csv (docs/dataset.md requires it) the
    // dataset is refused, naming the file.
    const fs::path ds = scratch("bad_dataset");
    std::ofstream(ds / "flight.json") << R"({"format":"ardrone-dataset","version":1,
        "camera":"front","width":640,"height":360,"fps":30})";
    std::ofstream(ds / "video.h264") << "x";
    const fs::path out = ds / "cal.json";
    const CmdResult r = gs::test::run_cli("calibrate " + ds.string() +
                                          " --board 9x6 --square 0.05 --out " + out.string());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("frames.csv"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(out));
}

TEST(CalibrateCli, BlurryAndPartialBoardsGetTheirOwnMessage) {
    // Four good frames, one blurred past the sharpness limit and one with half the board covered:
    // each bad image gets a line saying why it was skipped, the calibration uses the good ones.
    const fs::path dir = scratch("blurry_partial");
    for (int i = 0; i < 4; ++i) {
        char name[16];
        std::snprintf(name, sizeof name, "good%d.jpg", i);
        fs::copy_file(frame(i), dir / name);
    }
    const cv::Mat img = cv::imread(frame(4), cv::IMREAD_COLOR);
    cv::Mat blurred;
    cv::GaussianBlur(img, blurred, {0, 0}, 2.5);
    cv::imwrite((dir / "x_blurred.png").string(), blurred);
    cv::Mat partial = img.clone();
    partial(cv::Rect(320, 0, 320, 360)).setTo(cv::Scalar::all(128));
    cv::imwrite((dir / "y_partial.png").string(), partial);
    const fs::path out = dir / "cal.json";
    const CmdResult r = gs::test::run_cli("calibrate " + dir.string() +
                                          " --board 9x6 --square 0.05 --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    // The progress line of one image: "[ 5/6] x_blurred.png   board blurry ...".
    auto line_of = [&](const char* name) {
        std::string key("] ");
        key.append(name);
        const auto at = r.out.find(key);
        if (at == std::string::npos) return std::string();
        const auto end = r.out.find('\n', at);
        return r.out.substr(at, end == std::string::npos ? std::string::npos : end - at);
    };
    EXPECT_NE(line_of("x_blurred.png").find("board blurry"), std::string::npos) << r.out;
    EXPECT_NE(line_of("y_partial.png").find("board not found"), std::string::npos) << r.out;
    EXPECT_NE(line_of("y_partial.png").find("whole 9x6 board"), std::string::npos) << r.out;
    EXPECT_NE(line_of("good3.jpg").find("board found"), std::string::npos) << r.out;
    const auto j = nlohmann::json::parse(std::ifstream(out));
    EXPECT_EQ(j["views"], 4);
}

TEST(CalibrateCli, OnlyBlurryBoardsSayBlurry) {
    const fs::path dir = scratch("only_blurry");
    for (int i = 0; i < 2; ++i) {
        cv::Mat blurred;
        cv::GaussianBlur(cv::imread(frame(i), cv::IMREAD_COLOR), blurred, {0, 0}, 2.5);
        char name[16];
        std::snprintf(name, sizeof name, "b%d.png", i);
        cv::imwrite((dir / name).string(), blurred);
    }
    const fs::path out = dir / "cal.json";
    const CmdResult r = gs::test::run_cli("calibrate " + dir.string() +
                                          " --board 9x6 --square 0.05 --out " + out.string());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("2 blurry, 0 without the board"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("hold it still"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("No calibration written"), std::string::npos);
    EXPECT_FALSE(fs::exists(out));
}

TEST(CalibrateCli, NoBoardAnywhereFailsWithoutAFile) {
    const fs::path dir = scratch("no_board");
    // Three frames with no chessboard: a grey field, noise, and a real frame with the board
    // painted over.
    cv::imwrite((dir / "a.png").string(), cv::Mat(360, 640, CV_8UC1, cv::Scalar(128)));
    cv::Mat noise(360, 640, CV_8UC1);
    cv::randu(noise, 0, 255);
    cv::imwrite((dir / "b.png").string(), noise);
    cv::Mat painted = cv::imread(frame(0));
    cv::rectangle(painted, cv::Rect(100, 30, 440, 300), cv::Scalar(90, 90, 90), cv::FILLED);
    cv::imwrite((dir / "c.png").string(), painted);
    const fs::path out = dir / "cal.json";
    const CmdResult r = gs::test::run_cli("calibrate " + dir.string() +
                                          " --board 9x6 --square 0.05 --out " + out.string());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("found in none of the 3 image(s)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("No calibration written"), std::string::npos);
    EXPECT_FALSE(fs::exists(out));
}

TEST(CalibrateCli, WrongBoardSizeFailsWithoutAFile) {
    const fs::path out = scratch("wrong_board") / "cal.json";
    const CmdResult r = gs::test::run_cli("calibrate " + kFrames +
                                          " --board 7x7 --square 0.05 --out " + out.string());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("7x7 board was found in none of the 11"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("inner corners"), std::string::npos);
    EXPECT_FALSE(fs::exists(out));
    // 8x6 fits inside a 9x6 board in one frame only: too few views, still no file.
    const CmdResult r8 = gs::test::run_cli("calibrate " + kFrames +
                                           " --board 8x6 --square 0.05 --out " + out.string());
    EXPECT_NE(r8.exit_code, 0);
    EXPECT_NE(r8.out.find("at least 3"), std::string::npos) << r8.out;
    EXPECT_FALSE(fs::exists(out));
}

TEST(CalibrateCli, MixedImageSizesFail) {
    const fs::path dir = scratch("mixed");
    fs::copy_file(frame(0), dir / "a.jpg");
    fs::copy_file(frame(1), dir / "b.jpg");
    cv::Mat small;
    cv::resize(cv::imread(frame(2)), small, {320, 180});
    cv::imwrite((dir / "c.jpg").string(), small);
    const fs::path out = dir / "cal.json";
    const CmdResult r = gs::test::run_cli("calibrate " + dir.string() +
                                          " --board 9x6 --square 0.05 --out " + out.string());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("c.jpg is 320x180 but the earlier images are 640x360"), std::string::npos)
        << r.out;
    EXPECT_FALSE(fs::exists(out));
}

TEST(CalibrateCli, BadOptionsAreRefused) {
    const fs::path out = scratch("bad_options") / "cal.json";
    const std::string tail = " --out " + out.string();
    for (const std::string& args :
         {kFrames + " --board 9 --square 0.05", kFrames + " --board 2x6 --square 0.05",
          kFrames + " --board 9x6 --square 0", kFrames + " --board 9x6 --square -1",
          kFrames + " --board 9x6 --square 50", kFrames + " --board 9x6 --square 0.05 --step 0",
          std::string("/nonexistent/dir --board 9x6 --square 0.05"), kFrames + " --square 0.05"}) {
        const CmdResult r = gs::test::run_cli("calibrate " + args + tail);
        EXPECT_NE(r.exit_code, 0) << args;
        EXPECT_FALSE(r.out.empty()) << args;
        EXPECT_FALSE(fs::exists(out)) << args;
    }
    const CmdResult mm =
        gs::test::run_cli("calibrate " + kFrames + " --board 9x6 --square 50" + tail);
    EXPECT_NE(mm.out.find("give metres"), std::string::npos) << mm.out;
}

}  // namespace
