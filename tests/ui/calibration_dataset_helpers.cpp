#include "calibration_dataset.hpp"

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <fstream>

namespace gs::ui::test {

namespace fs = std::filesystem;

fs::path chessboard_fixture(int i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame%04d.jpg", i);
    return fs::path(GS_FIXTURES_DIR) / "real" / "calibration" / "rjw57_ardrone2_front_chessboard" /
           name;
}

std::string write_chessboard_dataset(const fs::path& dir, const ChessboardDatasetOptions& opt) {
    constexpr int kW = 640, kH = 360;
    constexpr double kFps = 5.0;
    std::error_code ec;
    fs::remove_all(dir, ec);
    fs::create_directories(dir / "frames", ec);
    if (ec) return "cannot create " + dir.string() + ": " + ec.message();
    const int n = kChessboardFrames + (opt.add_empty_frame ? 1 : 0);
    std::ofstream csv(dir / "frames.csv");
    csv << "frame,t_ms,roll_deg,pitch_deg,yaw_deg,vx_mps,vy_mps,vz_mps,altitude_m\n";
    for (int i = 0; i < n; ++i) {
        cv::Mat img;
        if (i < kChessboardFrames) {
            img = cv::imread(chessboard_fixture(i).string(), cv::IMREAD_COLOR);
            if (img.empty()) return "cannot read " + chessboard_fixture(i).string();
            if (img.cols != kW || img.rows != kH) cv::resize(img, img, {kW, kH});
        } else {
            img = cv::Mat(kH, kW, CV_8UC3);
            cv::randu(img, cv::Scalar::all(90), cv::Scalar::all(140));
        }
        char name[32];
        std::snprintf(name, sizeof name, "%06d.png", i);
        if (!cv::imwrite((dir / "frames" / name).string(), img, {cv::IMWRITE_PNG_COMPRESSION, 1}))
            return std::string("cannot write ") + name;
        csv << i << ',' << i * 1000.0 / kFps << ",0,0,0,0,0,0,1\n";
    }
    const CameraCalibration& c = opt.calibration;
    const nlohmann::json fj = {
        {"format", "ardrone-dataset"},
        {"version", 1},
        {"camera", "front"},
        {"width", kW},
        {"height", kH},
        {"fps", kFps},
        {"frames", n},
        {"images", "frames"},
        {"source", "rjw57 AR.Drone 2 front chessboard frames (test)"},
        {"calibration",
         {{"fx", c.fx}, {"fy", c.fy}, {"cx", c.cx}, {"cy", c.cy}, {"dist", c.dist}}}};
    std::ofstream(dir / "flight.json") << fj.dump(2);
    return {};
}

}  // namespace gs::ui::test
