// Render and encode time per frame for the simulated front camera (one core): flies a scene's
// straight path at 1 m/s with a little roll wobble, prints p50/p90/p99/max for the renderer and
// the H.264 encoder. Usage: bench_render_bench [scene.json] [frames] [png_dir]
// (png_dir: write every 30th frame there as PNG to look at).

#include "bench/timing.hpp"
#include "drone/core/camera_calibration.hpp"
#include "drone/sim/renderer.hpp"
#include "drone/sim/scene.hpp"
#include "drone/video/h264_encoder.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace {

using gs::bench::thread_cpu_ms;
void report(const char* what, std::vector<double> ms) {
    gs::bench::report(what, std::move(ms), 8);
}

}  // namespace

int main(int argc, char** argv) {
    cv::setNumThreads(1);  // the budget is per core
    const std::string path =
        argc > 1 ? argv[1] : std::string(GS_ASSETS_DIR) + "/scenes/warehouse.json";
    const int frames = argc > 2 ? std::max(1, std::atoi(argv[2])) : 300;
    const std::string png_dir = argc > 3 ? argv[3] : "";
    auto scene = gs::sim::load_scene(path);
    if (!scene) {
        std::fprintf(stderr, "%s\n", gs::sim::to_string(scene.error()).c_str());
        return 1;
    }
    const auto t_build0 = std::chrono::steady_clock::now();
    auto renderer = gs::sim::Renderer::create(*scene, gs::builtin_calibration(gs::CameraId::Front),
                                              gs::sim::CameraKind::Front);
    if (!renderer) {
        std::fprintf(stderr, "%s\n", gs::sim::to_string(renderer.error()).c_str());
        return 1;
    }
    const double build_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_build0)
            .count();
    auto encoder = gs::video::H264Encoder::create({});
    if (!encoder) {
        std::fprintf(stderr, "%s\n", gs::video::to_string(encoder.error()).c_str());
        return 1;
    }
    const auto st = renderer->stats();
    std::printf("scene %s: %d primitives, %d textures, set-up %.0f ms\n", path.c_str(),
                st.primitives, st.textures, build_ms);
    cv::Mat img;
    std::vector<std::uint8_t> au;
    std::vector<double> render_ms, encode_ms, render_cpu_ms, encode_cpu_ms;
    std::size_t bytes = 0;
    for (int i = 0; i < frames; ++i) {
        const double t = i / 30.0;
        gs::sim::Pose p = scene->start;
        p.x_m += 1.0 * t;
        p.roll_deg = 2.0 * std::sin(t * 3.0);
        p.pitch_deg = -4.0 + 0.5 * std::sin(t * 2.0);
        const double c0 = thread_cpu_ms();
        const auto t0 = std::chrono::steady_clock::now();
        renderer->render(p, img);
        const auto t1 = std::chrono::steady_clock::now();
        const double c1 = thread_cpu_ms();
        bool idr = false;
        auto n = (*encoder)->encode(img, au, idr);
        const auto t2 = std::chrono::steady_clock::now();
        const double c2 = thread_cpu_ms();
        render_cpu_ms.push_back(c1 - c0);
        encode_cpu_ms.push_back(c2 - c1);
        if (!n) {
            std::fprintf(stderr, "encode: %s\n", gs::video::to_string(n.error()).c_str());
            return 1;
        }
        bytes += *n;
        render_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        encode_ms.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
        if (!png_dir.empty() && i % 30 == 0) {
            char name[64];
            std::snprintf(name, sizeof name, "/frame_%04d.png", i);
            cv::imwrite(png_dir + name, img);
        }
    }
    std::printf("wall time:\n");
    report("render", render_ms);
    report("encode", encode_ms);
    std::printf("thread CPU time:\n");
    report("render", render_cpu_ms);
    report("encode", encode_cpu_ms);
    std::printf("drawn primitives (last frame): %d; H.264 %.0f kbit/s\n",
                renderer->stats().primitives_drawn, double(bytes) * 8.0 / (frames / 30.0) / 1000.0);
    return 0;
}
