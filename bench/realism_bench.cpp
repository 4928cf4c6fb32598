// Camera-effects time per frame of the realism layer (drone/sim/realism.hpp), one core: renders a
// scene's straight path at 1.5 m/s with a yaw and roll wobble (up to ~60 deg/s), then applies
// the real-camera preset's geometry (rolling shutter 25 ms, motion blur 12 ms: the per-pixel
// resampling) and its photometry, timing each part. Prints p50/p90/p99/max of thread CPU time.
// Usage: bench_realism_bench [scene.json] [frames] [--dump FILE | --compare FILE] [--png DIR]
//                            [--scene-effects]
//   --scene-effects also the preset's scene effects (half the walls plain, the glossy floor's
//                   mirror pass, a person crossing), timed in "render"
//   --dump FILE     write every output frame's bytes to FILE (to compare two builds)
//   --compare FILE  compare every output frame with FILE's: max and mean absolute difference
//   --png DIR       write every 30th output frame as PNG (and its clean render) to look at

#include "bench/timing.hpp"
#include "drone/core/camera_calibration.hpp"
#include "drone/sim/realism.hpp"
#include "drone/sim/renderer.hpp"
#include "drone/sim/scene.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

namespace {

using gs::bench::report;
using gs::bench::thread_cpu_ms;

}  // namespace

int main(int argc, char** argv) {
    cv::setNumThreads(1);  // the budget is per core
    std::string path = std::string(GS_ASSETS_DIR) + "/scenes/thesis_pillar_left.json";
    int frames = 150;
    std::string dump, compare, png_dir;
    bool scene_effects = false;
    int positional = 0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--dump" && i + 1 < argc) {
            dump = argv[++i];
        } else if (a == "--compare" && i + 1 < argc) {
            compare = argv[++i];
        } else if (a == "--scene-effects") {
            scene_effects = true;
        } else if (a == "--png" && i + 1 < argc) {
            png_dir = argv[++i];
        } else if (positional == 0) {
            path = a;
            ++positional;
        } else {
            frames = std::max(1, std::atoi(a.c_str()));
        }
    }
    auto scene = gs::sim::load_scene(path);
    if (!scene) {
        std::fprintf(stderr, "%s\n", gs::sim::to_string(scene.error()).c_str());
        return 1;
    }
    const gs::sim::RealismOptions preset = gs::sim::RealismOptions::real_camera();
    std::vector<gs::sim::PersonTrack> people;
    if (scene_effects) {
        gs::sim::apply_scene_effects(*scene, preset, 11);
        people = gs::sim::plan_people(preset, scene->room, scene->start.x_m, scene->start.y_m,
                                      scene->start.yaw_deg, 1.5 * 1.25, 11);
    }
    const auto calib = gs::builtin_calibration(gs::CameraId::Front);
    auto renderer = gs::sim::Renderer::create(
        *scene, calib, gs::sim::CameraKind::Front,
        scene_effects ? gs::sim::render_options(preset) : gs::sim::RenderOptions{});
    if (!renderer) {
        std::fprintf(stderr, "%s\n", gs::sim::to_string(renderer.error()).c_str());
        return 1;
    }
    gs::sim::RealismOptions geo, photo;
    geo.rolling_shutter_ms = preset.rolling_shutter_ms;
    geo.exposure_ms = preset.exposure_ms;
    photo = preset;
    photo.rolling_shutter_ms = photo.exposure_ms = 0;
    photo.low_texture_walls_pct = photo.glossy_floor_pct = photo.people_crossing = 0;
    gs::sim::CameraEffects fx_geo(calib, geo, 11), fx_photo(calib, photo, 11);
    std::printf("scene %s, %dx%d, %d frames; geometry: rolling shutter %.0f ms, exposure %.0f ms\n",
                path.c_str(), calib.width, calib.height, frames, geo.rolling_shutter_ms,
                geo.exposure_ms);

    std::ofstream dump_out;
    if (!dump.empty()) dump_out.open(dump, std::ios::binary);
    std::ifstream cmp_in;
    if (!compare.empty()) {
        cmp_in.open(compare, std::ios::binary);
        if (!cmp_in) {
            std::fprintf(stderr, "cannot read %s\n", compare.c_str());
            return 1;
        }
    }
    int max_diff = 0;
    double sum_diff = 0;
    std::size_t n_diff = 0, n_values = 0;

    cv::Mat img, clean;
    std::vector<double> render_ms, geo_ms, photo_ms;
    gs::sim::Pose last{};
    const double dt = 1 / 30.0;
    for (int i = 0; i < frames; ++i) {
        const double t = i * dt;
        gs::sim::Pose p = scene->start;
        p.x_m += 1.5 * t;
        p.yaw_deg += 15.0 * std::sin(t * 4.0);  // up to 60 deg/s
        p.roll_deg = 3.0 * std::sin(t * 5.0);
        p.pitch_deg = -5.0 + 0.5 * std::sin(t * 2.0);
        const double c0 = thread_cpu_ms();
        if (!people.empty()) {
            std::vector<gs::sim::Obstacle> movers;
            for (const auto& q : people)
                if (q.present(t)) movers.push_back(q.at(t));
            renderer->set_movers(movers);
        }
        renderer->render(p, img);
        const double c1 = thread_cpu_ms();
        if (!png_dir.empty() && i % 30 == 0) clean = img.clone();
        const auto motion =
            gs::sim::camera_motion(i > 0 ? last : p, p, dt, gs::sim::CameraKind::Front);
        fx_geo.apply(img, t, motion, renderer->inverse_depth());
        const double c2 = thread_cpu_ms();
        fx_photo.apply(img, t, motion, {});
        const double c3 = thread_cpu_ms();
        last = p;
        render_ms.push_back(c1 - c0);
        geo_ms.push_back(c2 - c1);
        photo_ms.push_back(c3 - c2);
        const std::size_t bytes = img.total() * img.elemSize();
        if (dump_out.is_open())
            dump_out.write(reinterpret_cast<const char*>(img.data), std::streamsize(bytes));
        if (cmp_in.is_open()) {
            std::vector<std::uint8_t> ref(bytes);
            if (!cmp_in.read(reinterpret_cast<char*>(ref.data()), std::streamsize(bytes))) {
                std::fprintf(stderr, "%s ends at frame %d\n", compare.c_str(), i);
                return 1;
            }
            for (std::size_t k = 0; k < bytes; ++k) {
                const int d = std::abs(int(ref[k]) - int(img.data[k]));
                max_diff = std::max(max_diff, d);
                sum_diff += d;
                n_diff += d > 0;
            }
            n_values += bytes;
        }
        if (!png_dir.empty() && i % 30 == 0) {
            char name[96];
            std::snprintf(name, sizeof name, "/frame_%04d.png", i);
            cv::imwrite(png_dir + name, img);
            std::snprintf(name, sizeof name, "/clean_%04d.png", i);
            cv::imwrite(png_dir + name, clean);
        }
    }
    std::printf("thread CPU time per frame:\n");
    report("render", render_ms);
    report("geometry", geo_ms);
    report("photometry", photo_ms);
    if (n_values > 0)
        std::printf("versus %s: max |difference| %d, mean %.5f, %.4f %% of values differ\n",
                    compare.c_str(), max_diff, sum_diff / double(n_values),
                    100.0 * double(n_diff) / double(n_values));
    return 0;
}
