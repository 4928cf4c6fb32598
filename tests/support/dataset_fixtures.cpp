#include "support/dataset_fixtures.hpp"

#include <opencv2/imgcodecs.hpp>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace gs::test {

TempDir::TempDir() {
    std::string tmpl = "/tmp/gs_dataset_test_XXXXXX";
    if (::mkdtemp(tmpl.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = tmpl;
}

TempDir::~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
}

void write_file(const std::filesystem::path& p, const std::string& text) {
    std::filesystem::create_directories(p.parent_path());
    std::ofstream out(p, std::ios::binary);
    out << text;
}

std::string read_file(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

cv::Mat test_image(int index, int width, int height) {
    cv::Mat m(height, width, CV_8UC3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            m.at<cv::Vec3b>(y, x) = cv::Vec3b(static_cast<uchar>((x + index * 7) & 0xFF),
                                              static_cast<uchar>((y * 3 + index) & 0xFF),
                                              static_cast<uchar>(index & 0xFF));
    return m;
}

std::string flight_json(int width, int height, double fps, const std::string& extra) {
    std::ostringstream s;
    s << "{\n  \"format\": \"ardrone-dataset\",\n  \"version\": 1,\n  \"camera\": \"front\",\n"
      << "  \"width\": " << width << ",\n  \"height\": " << height << ",\n  \"fps\": " << fps;
    if (!extra.empty()) s << ",\n  " << extra;
    s << "\n}\n";
    return s.str();
}

void make_png_dataset(const std::filesystem::path& dir, int n, int width, int height) {
    write_file(dir / "flight.json",
               flight_json(width, height, 25,
                           "\"calibration\": {\"fx\": 50.5, \"fy\": 51.25, \"cx\": 32, \"cy\": 24, "
                           "\"dist\": [-0.5, 0.25, 0.001, 0.002, 0.0]}"));
    std::string csv = "frame,t_ms,roll_deg,pitch_deg,yaw_deg,altitude_m\n";
    for (int i = 0; i < n; ++i) {
        csv += std::to_string(i) + "," + std::to_string(40 * i) + "," + std::to_string(i) + "," +
               std::to_string(-i * 0.5) + "," + std::to_string(10 * i) + ",1.5\n";
    }
    write_file(dir / "frames.csv", csv);
    std::filesystem::create_directories(dir / "frames");
    for (int i = 0; i < n; ++i) {
        char name[32];
        std::snprintf(name, sizeof name, "%06d.png", i);
        cv::imwrite((dir / "frames" / name).string(), test_image(i, width, height));
    }
}

void make_assets(const std::filesystem::path& dir) {
    write_file(dir / "calibration/ardrone2_front.json",
               R"({"fx": 560.0, "fy": 560.0, "cx": 319.5, "cy": 179.5,
                   "dist": [-0.5, 0.3, 0.0, 0.0, 0.0], "width": 640, "height": 360,
                   "source": "test front"})");
    write_file(dir / "calibration/ardrone2_bottom.json",
               R"({"fx": 700.0, "fy": 700.0, "cx": 319.5, "cy": 179.5,
                   "dist": [0.0, 0.0, 0.0, 0.0, 0.0], "width": 640, "height": 360,
                   "source": "test bottom"})");
}

std::vector<std::uint8_t> fake_access_unit(bool idr, int payload, std::uint8_t fill) {
    std::vector<std::uint8_t> au = {0,   0, 0, 1, static_cast<std::uint8_t>(idr ? 0x65 : 0x41),
                                    0x88};  // first_mb_in_slice = 0
    for (int i = 0; i < payload; ++i) au.push_back(static_cast<std::uint8_t>(fill | 0x10));
    return au;
}

void copy_attitude_only(const std::filesystem::path& from, const std::filesystem::path& to) {
    namespace fs = std::filesystem;
    fs::create_directories(to.parent_path());
    fs::copy(from, to, fs::copy_options::recursive);
    std::istringstream in(read_file(from / "frames.csv"));
    std::ofstream out(to / "frames.csv", std::ios::trunc);
    std::string line;
    bool header = true;
    while (std::getline(in, line)) {
        // frame,t_ms,roll_deg are the first three columns the writer puts out.
        std::size_t end = 0;
        for (int i = 0; i < 3 && end != std::string::npos; ++i)
            end = line.find(',', i == 0 ? 0 : end + 1);
        out << (header ? "frame,t_ms,roll_deg" : line.substr(0, end)) << '\n';
        header = false;
    }
    fs::remove(to / "navdata.csv");
}

}  // namespace gs::test
