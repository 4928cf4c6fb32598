// `ardrone-gs odometry DATASET`: the thesis' visual odometry (§3.1) over a recorded or generated
// flight: per-sample estimates, and with ground truth the per-sample absolute errors, their
// min / max / mean (eq. 6.1, tables 6.1-6.4) and the trajectory error (eq. 6.2).
// A bottom-camera dataset (docs/dataset.md) runs single-camera with altitude_m as the distance;
// with top/ and distances.csv beside it, both cameras are combined (eq. 3.16-3.18).
// `--generate TEST` first renders one of the thesis' four test flights into DATASET.
#include "app/cli_options.hpp"
#include "app/command.hpp"
#include "app/pipeline.hpp"
#include "app/replay_run.hpp"
#include "drone/dataset/dataset.hpp"
#include "drone/dataset/frame_store.hpp"
#include "drone/dataset/video_frames.hpp"
#include "drone/sim/odometry_flights.hpp"
#include "vision/odometry.hpp"

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

namespace gs::app::cmd_odometry {
namespace {
namespace fs = std::filesystem;

struct Opts {
    std::string dataset;
    std::string out;
    bool single = false;
    bool thesis = false;
    bool summary = false;
    std::string yaw = "visual";
    DatasetInputOptions input;  // --calibration (the bottom camera's), --fps
    std::vector<std::string> set;
    // generation
    std::string generate;
    std::uint64_t seed = 1;
    double duration_s = 0;
    double imu_noise_deg = -1;  // < 0: the generator's default
    double imu_bias_deg = 0;
    double imu_bias_walk_dps = 0;
    bool no_top = false;
    double top_delay_s = 0;
};

std::string num(double v, int prec = 4) {
    if (!std::isfinite(v)) return "-";
    char b[48];
    std::snprintf(b, sizeof b, "%.*f", prec, v);
    return b;
}

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return std::nan("");
    const auto k = static_cast<std::size_t>(std::clamp(q, 0.0, 1.0) * double(v.size() - 1));
    std::nth_element(v.begin(), v.begin() + long(k), v.end());
    return v[k];
}

std::string error_table(const vision::OdometryErrors& e) {
    std::ostringstream o;
    auto row = [&](const char* name, const vision::ErrorStats& s, double k, const char* unit) {
        char b[160];
        std::snprintf(b, sizeof b, "%-20s %10s %-3s %10s %-3s %10s %-3s\n", name,
                      num(s.min * k).c_str(), unit, num(s.max * k).c_str(), unit,
                      num(s.mean * k).c_str(), unit);
        o << b;
    };
    char h[160];
    std::snprintf(h, sizeof h, "%-20s %14s %14s %14s\n", "", "Min", "Max", "Mean");
    o << h;
    row("X Axis", e.x, 100, "cm");
    row("Y Axis", e.y, 100, "cm");
    row("Rotation Axis", e.yaw, 1, "deg");
    if (e.yaw_nav.n > 0) row("Rotation (navdata)", e.yaw_nav, 1, "deg");
    o << "samples " << e.x.n << "; trajectory: travelled " << num(e.distance_travelled_m, 3)
      << " m, end-point error " << num(e.end_error_m * 100, 2) << " cm (" << num(e.end_error_pct, 2)
      << " %), max error " << num(e.max_path_error_m * 100, 2) << " cm, end heading error "
      << num(e.end_yaw_error_deg, 2) << " deg";
    if (std::isfinite(e.nav_end_error_m))
        o << "; navdata path end-point error " << num(e.nav_end_error_m * 100, 2) << " cm";
    o << "\n";
    return o.str();
}

nlohmann::json stats_json(const vision::ErrorStats& s) {
    return {{"min", s.min}, {"max", s.max}, {"mean", s.mean}, {"n", s.n}};
}

int run(const Opts& o) {
    const fs::path dir = o.dataset;
    if (!o.generate.empty()) {
        auto test = sim::odometry_test_from_string(o.generate);
        if (!test)
            throw fail("unknown test '" + o.generate +
                       "' (hover, translation, translation_rotation, rotation)");
        sim::OdometryFlightParams gp;
        gp.test = *test;
        gp.duration_s = o.duration_s;
        gp.top_camera = !o.no_top;
        gp.top_delay_s = o.top_delay_s;
        if (o.imu_noise_deg >= 0) gp.nav_attitude_noise_deg = o.imu_noise_deg;
        gp.nav_attitude_bias_deg = o.imu_bias_deg;
        gp.nav_attitude_bias_walk_dps = o.imu_bias_walk_dps;
        auto r = sim::write_odometry_flight(dir, gp, o.seed);
        if (!r) throw fail("cannot generate the flight: " + r.error());
        std::cout << "generated " << sim::to_string(*test) << " (seed " << o.seed
                  << "): " << r->frames << " frames, " << num(r->duration_s, 1) << " s, path "
                  << num(r->path_length_m, 3) << " m, rendering " << num(r->render_ms / 1000, 1)
                  << " s, writing " << num(r->write_ms / 1000, 1) << " s\n";
    }

    auto ds = open_input_dataset(dir.string(), o.input);
    if (!ds) throw fail(ds.error());
    const dataset::DatasetInfo& info = ds->info();
    if (info.camera != CameraId::Bottom)
        throw fail(dir.string() + ": the odometry needs a bottom-camera dataset (camera is '" +
                   to_string(info.camera) + "')");
    auto store = !ds->image_files().empty() ? dataset::open_image_frames(*ds)
                                            : dataset::open_video_frames(*ds);
    if (!store) throw fail(to_string(store.error()));
    auto extras = sim::read_two_camera_extras(dir, ds->frame_count());
    if (!extras) throw fail(extras.error());
    const bool two = !o.single && !extras->top_images.empty();

    vision::OdometryParams params;
    if (o.thesis) {
        params.centre_on_principal_point = false;
        params.tilt_compensation = false;
        params.image_tilt = false;
    }
    auto ys = vision::yaw_source_from_string(o.yaw);
    if (!ys) throw fail("unknown --yaw '" + o.yaw + "' (visual, navdata, fused)");
    params.yaw_source = *ys;
    if (auto e = vision::apply_param_overrides(vision::odometry_param_table(), params, o.set,
                                               "--set", "--odometry"))
        throw fail(*e);

    auto bottom_calib = input_calibration(*ds, o.input);
    if (!bottom_calib) throw fail(bottom_calib.error());
    const CameraCalibration bottom_cal =
        bottom_calib->with_size_if_unknown(info.width, info.height);
    std::optional<CameraCalibration> top_cal;
    if (two)
        top_cal = extras->top_calibration
                      ? extras->top_calibration->with_size_if_unknown(info.width, info.height)
                      : bottom_cal;
    vision::VisualOdometry vo(bottom_cal, top_cal, params);

    const auto& rows = ds->frames();
    bool have_gt = !rows.empty();
    for (const dataset::FrameRow& r : rows)
        have_gt = have_gt && known(r.gt.x_m) && known(r.gt.y_m) && known(r.gt.yaw_deg);
    std::vector<vision::PlanarPose> truth;
    vision::PlanarPose start;
    if (have_gt) {
        truth.reserve(rows.size());
        for (const dataset::FrameRow& r : rows) truth.push_back({r.gt.x_m, r.gt.y_m, r.gt.yaw_deg});
        start = truth[0];
    }
    vo.reset(start);

    std::cout << "odometry: " << dir.string() << ": " << rows.size() << " frames at "
              << num(info.fps, 1) << " fps, "
              << (two ? "two cameras (bottom + top)" : "single camera (bottom + altitude)")
              << ", yaw " << vision::to_string(params.yaw_source)
              << (params.centre_on_principal_point ? "" : ", thesis pixel-origin homography")
              << (have_gt ? ", ground truth present" : ", no ground truth") << "\n";

    std::vector<vision::OdometrySample> samples;
    samples.reserve(rows.size());
    std::vector<double> ms;
    cv::Mat bottom, top;
    if (!o.summary)
        std::cout << "frame  t_ms      dx_cm    dy_cm    dyaw_deg  x_m      y_m      yaw_deg  "
                     "flags\n";
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const dataset::FrameRow& r = rows[i];
        if (auto e = (*store)->read(static_cast<std::int64_t>(i), bottom))
            throw fail(to_string(*e));
        vision::OdometryInput in = to_odometry_input(r.nav, r.nav.t_ns, bottom);
        if (!extras->bottom_m.empty() && known(extras->bottom_m[i]))
            in.bottom_distance_m = extras->bottom_m[i];
        if (two) {
            top = cv::imread(extras->top_images[i].string(), cv::IMREAD_GRAYSCALE);
            if (top.empty()) throw fail("cannot read " + extras->top_images[i].string());
            in.top = top;
            in.top_distance_m = extras->top_m.empty() ? kUnknown : extras->top_m[i];
        }
        const vision::OdometrySample& s = vo.update(in);
        samples.push_back(s);
        if (i > 0) ms.push_back(s.total_ms);
        if (!o.summary) {
            char b[200];
            std::snprintf(b, sizeof b, "%-6lld %-9s %8s %8s %9s %8s %8s %8s %s%s%s\n",
                          static_cast<long long>(r.frame), num(double(r.nav.t_ns) / 1e6, 1).c_str(),
                          num(s.out.forward_m * 100, 3).c_str(),
                          num(s.out.right_m * 100, 3).c_str(), num(s.out.yaw_deg, 3).c_str(),
                          num(s.pose.x_m, 3).c_str(), num(s.pose.y_m, 3).c_str(),
                          num(s.pose.yaw_deg, 2).c_str(), s.valid || i == 0 ? "" : "invalid ",
                          s.out.spike_zeroed ? "spike " : "", s.out.rotation_gated ? "gated" : "");
            std::cout << b;
        }
    }

    double mean_ms = 0;
    for (double v : ms) mean_ms += v;
    if (!ms.empty()) mean_ms /= double(ms.size());
    int invalid = 0, spikes = 0, gated = 0;
    for (std::size_t i = 1; i < samples.size(); ++i) {
        invalid += samples[i].valid ? 0 : 1;
        spikes += samples[i].out.spike_zeroed ? 1 : 0;
        gated += samples[i].out.rotation_gated ? 1 : 0;
    }
    std::cout << "samples " << samples.size() << ": " << invalid << " without estimate, " << spikes
              << " spike-zeroed, " << gated << " rotation-gated; time per sample mean "
              << num(mean_ms, 2) << " ms, p95 " << num(percentile(ms, 0.95), 2) << " ms\n";

    std::optional<vision::OdometryErrors> err;
    if (have_gt) {
        err = vision::evaluate_odometry(samples, truth);
        std::cout << error_table(*err);
    }

    if (!o.out.empty()) {
        const fs::path out = o.out;
        std::error_code ec;
        fs::create_directories(out, ec);
        if (ec) throw fail("cannot create " + out.string() + ": " + ec.message());
        const auto gt =
            have_gt ? vision::truth_from_poses(truth) : std::vector<vision::SampleTruth>{};
        std::ofstream f(out / "samples.csv");
        f << "frame,t_ms,valid,bottom_status,bottom_inliers,top_status,top_inliers,dx_m,dy_m,"
             "dyaw_deg,dyaw_visual_deg,dyaw_navdata_deg,spike_zeroed,rotation_gated,x_m,y_m,"
             "yaw_deg,nav_x_m,nav_y_m,nav_yaw_deg,gt_dx_m,gt_dy_m,gt_dyaw_deg,gt_x_m,gt_y_m,"
             "gt_yaw_deg,err_x_m,err_y_m,err_yaw_deg,ms\n";
        f.precision(9);
        for (std::size_t i = 0; i < samples.size(); ++i) {
            const auto& s = samples[i];
            auto v = [](double x) { return std::isfinite(x) ? std::to_string(x) : std::string(); };
            f << rows[i].frame << ',' << double(s.t_ns) / 1e6 << ',' << int(s.valid) << ','
              << vision::to_string(s.bottom.status) << ',' << s.bottom.inliers << ','
              << (two ? vision::to_string(s.top.status) : "") << ',' << s.top.inliers << ','
              << s.out.forward_m << ',' << s.out.right_m << ',' << s.out.yaw_deg << ','
              << s.yaw_visual_deg << ',' << v(s.yaw_navdata_deg) << ',' << int(s.out.spike_zeroed)
              << ',' << int(s.out.rotation_gated) << ',' << s.pose.x_m << ',' << s.pose.y_m << ','
              << s.pose.yaw_deg << ',' << s.nav_pose.x_m << ',' << s.nav_pose.y_m << ','
              << s.nav_pose.yaw_deg << ',';
            if (have_gt) {
                f << gt[i].forward_m << ',' << gt[i].right_m << ',' << gt[i].yaw_deg << ','
                  << truth[i].x_m << ',' << truth[i].y_m << ',' << truth[i].yaw_deg << ',';
                if (i > 0)
                    f << err->x_abs_m[i - 1] << ',' << err->y_abs_m[i - 1] << ','
                      << err->yaw_abs_deg[i - 1];
                else
                    f << ",,";
            } else {
                f << ",,,,,,,,";
            }
            f << ',' << s.total_ms << '\n';
        }
        nlohmann::ordered_json j;
        j["dataset"] = dir.string();
        j["cameras"] = two ? 2 : 1;
        j["yaw_source"] = vision::to_string(params.yaw_source);
        j["params"] = vision::odometry_param_table().to_map(params);
        j["samples"] = samples.size();
        j["invalid"] = invalid;
        j["spike_zeroed"] = spikes;
        j["rotation_gated"] = gated;
        j["ms_per_sample_mean"] = mean_ms;
        j["ms_per_sample_p95"] = percentile(ms, 0.95);
        if (err) {
            j["x_cm"] =
                stats_json({err->x.min * 100, err->x.max * 100, err->x.mean * 100, err->x.n});
            j["y_cm"] =
                stats_json({err->y.min * 100, err->y.max * 100, err->y.mean * 100, err->y.n});
            j["rotation_deg"] = stats_json(err->yaw);
            if (err->yaw_nav.n > 0) j["rotation_navdata_deg"] = stats_json(err->yaw_nav);
            j["distance_travelled_m"] = err->distance_travelled_m;
            j["end_error_m"] = err->end_error_m;
            j["end_error_pct"] = std::isfinite(err->end_error_pct)
                                     ? nlohmann::json(err->end_error_pct)
                                     : nlohmann::json(nullptr);
            j["max_path_error_m"] = err->max_path_error_m;
            j["end_yaw_error_deg"] = err->end_yaw_error_deg;
            if (std::isfinite(err->nav_end_error_m))
                j["navdata_end_error_m"] = err->nav_end_error_m;
        }
        std::ofstream(out / "summary.json") << j.dump(2) << "\n";
        if (err) std::ofstream(out / "errors.txt") << error_table(*err);
        if (!f) throw fail("cannot write " + (out / "samples.csv").string());
        std::cout << "wrote " << (out / "samples.csv").string() << ", summary.json"
                  << (err ? ", errors.txt" : "") << "\n";
    }
    return 0;
}

CommandRegistration reg(60, [](CLI::App& root) {
    auto o = std::make_shared<Opts>();
    auto* sub = root.add_subcommand(
        "odometry", "Visual odometry (thesis §3.1) over a bottom-camera or two-camera dataset");
    sub->add_option("DATASET", o->dataset,
                    "Dataset directory (with --generate: created), or a thesis-style image folder "
                    "with its IMU text file")
        ->required();
    sub->add_option("--out", o->out, "Write samples.csv, summary.json and errors.txt here")
        ->check(output_directory());
    sub->add_flag("--single", o->single, "Use the bottom camera only, even when top/ exists");
    sub->add_flag(
        "--thesis", o->thesis,
        "As the thesis computed it: homography about the pixel origin, no tilt compensation "
        "(neither from navdata nor from the images)");
    sub->add_option("--yaw", o->yaw, "Rotation source: visual, navdata or fused")
        ->capture_default_str();
    add_dataset_input_options(*sub, o->input,
                              "the bottom camera's of the dataset (flight.json's or the default); "
                              "the top camera keeps its own");
    sub->add_option(
        "--set", o->set,
        "Parameter override key=value (odo.*, filter.*; e.g. filter.smoothing_samples=4; "
        "`ardrone-gs params --odometry` lists every key)");
    sub->add_flag("--summary", o->summary, "Print only the summary, not every sample");
    sub->add_option("--generate", o->generate,
                    "First render a test flight into DATASET: hover, translation, "
                    "translation_rotation or rotation (15 fps, ground truth)");
    sub->add_option("--seed", o->seed, "Seed of the generated flight")
        ->capture_default_str()
        ->check(unsigned_integer());
    sub->add_option("--duration", o->duration_s, "Generated flight length in s (0: the test's)")
        ->check(number_in(0, 3600, "a duration in seconds"));
    sub->add_flag("--no-top", o->no_top, "Generate the bottom camera only");
    sub->add_option("--top-delay", o->top_delay_s,
                    "Generated top camera captures this many seconds late (unsynchronised)")
        ->check(number_in(0, 1, "a delay in seconds"));
    sub->add_option("--imu-noise", o->imu_noise_deg,
                    "Generated navdata roll/pitch white noise in degrees (default 0.05)")
        ->check(number_in(0, 10, "degrees"));
    sub->add_option("--imu-bias", o->imu_bias_deg,
                    "Generated navdata roll/pitch bias: starts at this many degrees per axis "
                    "(its sign from --seed)")
        ->check(number_in(0, 10, "degrees"));
    sub->add_option("--imu-bias-walk", o->imu_bias_walk_dps,
                    "... and drifts as a random walk of this many degrees per sqrt(second)")
        ->check(number_in(0, 10, "degrees per sqrt(second)"));
    set_action(*sub, [o] { return run(*o); });
});

}  // namespace
}  // namespace gs::app::cmd_odometry
