// Per-frame time of the obstacle classifiers on a pre-rendered synthetic flight (640x360, real
// AR.Drone 2 front calibration with its lens distortion, forward flight past a wall with a roll
// and yaw wobble), one thread. Prints wall-time percentiles per stage and the thread's CPU time
// per frame (the honest number on a shared machine).
//
// Usage: bench_vision_bench [frames=300] [classifier=all] [track_scale=0 (default)] [key=value ...]

#include "bench/timing.hpp"
#include "drone/core/unknown.hpp"
#include "vision/classifier.hpp"
#include "vision/synthetic_scene.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace gs::vision;
using gs::CameraCalibration;

namespace {

CameraCalibration ardrone_front() {
    // fixtures/real/calibration/tum_ardrone2_front_cal.yml
    CameraCalibration c;
    c.width = 640;
    c.height = 360;
    c.fx = 561.999146;
    c.fy = 561.782697;
    c.cx = 307.433982;
    c.cy = 190.144373;
    c.dist = {-0.50758, 0.24911, 0.000579, 0.000996, 0};
    return c;
}

struct Frame {
    cv::Mat bgr;
    FrameInput in;
};

std::vector<Frame> render(int n, const CameraCalibration& calib) {
    std::vector<TexturedPlane> planes;
    planes.push_back(make_plane({0, 0, 30}, {1, 0, 0}, {0, 1, 0}, 50, 30, 0.08, 1));
    planes.push_back(make_plane({0.8, 0, 12}, {0, 0, 1}, {0, 1, 0}, 16, 3, 0.02, 2));
    planes.push_back(make_plane({-1.5, 0, 12}, {0, 0, 1}, {0, 1, 0}, 16, 3, 0.02, 3));
    // Rendering is pinhole; distortion is applied by remapping, as the lens would.
    CameraCalibration pin = calib;
    pin.dist = {};
    cv::Mat mapx(calib.height, calib.width, CV_32FC1), mapy(calib.height, calib.width, CV_32FC1);
    std::vector<cv::Point2f> raw, und;
    for (int y = 0; y < calib.height; ++y)
        for (int x = 0; x < calib.width; ++x)
            raw.emplace_back(static_cast<float>(x), static_cast<float>(y));
    und.resize(raw.size());
    calib.undistort_points(raw, und);
    for (std::size_t i = 0; i < raw.size(); ++i) {
        mapx.at<float>(static_cast<int>(raw[i].y), static_cast<int>(raw[i].x)) = und[i].x;
        mapy.at<float>(static_cast<int>(raw[i].y), static_cast<int>(raw[i].x)) = und[i].y;
    }
    std::vector<Frame> frames(static_cast<std::size_t>(n));
    cv::Mat pinhole, grey;
    for (int i = 0; i < n; ++i) {
        const double t = i / 30.0;
        CameraPose pose;
        pose.position = {0.1 * std::sin(t), 0, 0.8 * t};
        pose.roll_deg = 4 * std::sin(2 * CV_PI * 0.4 * t);
        pose.pitch_deg = -3 + 1.5 * std::sin(2 * CV_PI * 0.3 * t);
        pose.yaw_deg = 6 * std::sin(2 * CV_PI * 0.2 * t);
        render_scene(planes, pin, pose, pinhole);
        cv::remap(pinhole, grey, mapx, mapy, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
        Frame& f = frames[static_cast<std::size_t>(i)];
        cv::cvtColor(grey, f.bgr, cv::COLOR_GRAY2BGR);
        f.in.image = f.bgr;
        f.in.t_ns = static_cast<std::int64_t>(std::llround(t * 1e9));
        f.in.attitude = {pose.roll_deg, pose.pitch_deg, pose.yaw_deg};
    }
    return frames;
}

using gs::bench::thread_cpu_ms;

double pct(std::vector<double> v, double p) {
    if (v.empty()) return gs::kUnknown;
    std::sort(v.begin(), v.end());
    const auto i = static_cast<std::size_t>(
        std::min<double>(static_cast<double>(v.size() - 1),
                         std::round(p / 100 * static_cast<double>(v.size() - 1))));
    return v[i];
}

}  // namespace

int main(int argc, char** argv) {
    const int n = argc > 1 ? std::atoi(argv[1]) : 300;
    const std::string which = argc > 2 ? argv[2] : "all";
    const double scale = argc > 3 ? std::atof(argv[3]) : 0.0;  // 0: the classifier's default
    cv::setNumThreads(1);                                      // the budget is one core
    const CameraCalibration calib = ardrone_front();
    std::printf("rendering %d frames 640x360 ...\n", n);
    const std::vector<Frame> frames = render(n, calib);

    for (std::string_view name : classifier_names()) {
        if (which != "all" && which != name) continue;
        auto c = make_classifier(name, calib);
        if (scale > 0 && c->set_param("track.track_scale", scale) != ParamStatus::Ok) return 2;
        ParamMap overrides;
        for (int a = 4; a < argc; ++a) {
            const std::string kv = argv[a];
            const auto eq = kv.find('=');
            if (eq != std::string::npos) overrides[kv.substr(0, eq)] = kv.substr(eq + 1);
        }
        for (const auto& [k, st] : c->params_from_map(overrides).rejected)
            std::printf("  parameter %s: %s\n", k.c_str(), to_string(st));
        std::vector<double> cpu, total, grey, pyr, lk, geo, det, cls, ovl, tracks;
        // Two passes; the first warms caches and allocations, the second is measured.
        for (int pass = 0; pass < 2; ++pass) {
            c->reset();
            for (const Frame& f : frames) {
                const double c0 = thread_cpu_ms();
                const FrameResult& r = c->process(f.in);
                const double c1 = thread_cpu_ms();
                if (pass == 0) continue;
                cpu.push_back(c1 - c0);
                total.push_back(r.timings.total_ms);
                grey.push_back(r.timings.grey_ms);
                pyr.push_back(r.timings.pyramid_ms);
                lk.push_back(r.timings.lk_ms);
                geo.push_back(r.timings.geometry_ms);
                det.push_back(r.timings.detect_ms);
                cls.push_back(r.timings.classify_ms);
                ovl.push_back(r.timings.overlay_ms);
                tracks.push_back(r.tracks);
            }
        }
        std::printf(
            "\n%s (track_scale %.2f, max_tracks %d), %d frames, ms per frame:\n",
            std::string(name).c_str(),
            [&] {
                double v = 0;
                (void)c->get_param("track.track_scale", v);
                return v;
            }(),
            [&] {
                double v = 0;
                (void)c->get_param("track.max_tracks", v);
                return static_cast<int>(v);
            }(),
            n);
        std::printf("  %-10s %7s %7s %7s %7s\n", "stage", "p50", "p90", "p99", "max");
        const std::pair<const char*, std::vector<double>*> rows[] = {
            {"grey", &grey},    {"pyramid", &pyr}, {"lk", &lk},
            {"geometry", &geo}, {"detect", &det},  {"classify", &cls},
            {"overlay", &ovl},  {"total", &total}, {"total cpu", &cpu}};
        for (const auto& [label, v] : rows)
            std::printf("  %-10s %7.3f %7.3f %7.3f %7.3f\n", label, pct(*v, 50), pct(*v, 90),
                        pct(*v, 99), pct(*v, 100));
        std::printf("  tracks     %7.0f %7.0f\n", pct(tracks, 50), pct(tracks, 90));
    }
    return 0;
}
