#include "app/cli_options.hpp"

#include "app/replay_outputs.hpp"
#include "app/replay_run.hpp"
#include "vision/classifier.hpp"

#include <charconv>
#include <cmath>

namespace gs::app {

CLI::Option* add_calibration_option(CLI::App& sub, std::string& file,
                                    const std::string& instead_of) {
    const CLI::Validator loads(
        [](std::string& path) -> std::string {
            auto c = load_calibration_file(path);
            if (!c) return to_string(c.error());
            return {};
        },
        "", "calibration file");
    return sub
        .add_option("--calibration", file,
                    "Camera calibration JSON (flight.json's calibration object or what `calibrate` "
                    "writes), used instead of " +
                        instead_of)
        ->type_name("FILE")
        ->check(loads);
}

CLI::Option* add_thesis_fps_option(CLI::App& sub, double& fps) {
    const CLI::Validator frame_rate(
        [](std::string& text) -> std::string {
            double v = 0;
            const char* end = text.data() + text.size();
            auto [p, ec] = std::from_chars(text.data(), end, v);
            if (ec != std::errc() || p != end || !std::isfinite(v) || v <= 0 || v > 1000)
                return "expected a frame rate in frames per second, > 0 and <= 1000; got '" + text +
                       "'";
            return {};
        },
        "", "frame rate");
    return sub
        .add_option("--fps", fps,
                    "Frame rate of a thesis-style image folder (default 25, or its imu_meta.json). "
                    "Only for such folders: a dataset directory has its own fps in flight.json")
        ->type_name("FPS")
        ->check(frame_rate);
}

void add_dataset_input_options(CLI::App& sub, DatasetInputOptions& o,
                               const std::string& calibration_instead_of) {
    add_calibration_option(sub, o.calibration, calibration_instead_of);
    add_thesis_fps_option(sub, o.fps);
}

Expected<dataset::Dataset, std::string> open_input_dataset(const std::string& path,
                                                           const DatasetInputOptions& o) {
    return open_any_dataset(path, given_fps(o.fps));
}

Expected<CameraCalibration, std::string> input_calibration(const dataset::Dataset& d,
                                                           const DatasetInputOptions& o) {
    ReplaySettings rs;
    if (!o.calibration.empty()) rs.calibration_file = o.calibration;
    return replay_calibration(d, rs);
}

void add_classifier_options(CLI::App& sub, std::string& classifier, std::vector<std::string>& set) {
    std::vector<std::string> names;
    for (auto n : vision::classifier_names()) names.emplace_back(n);
    sub.add_option("--classifier", classifier, "Obstacle classifier: thesis or flow")
        ->capture_default_str()
        ->check(CLI::IsMember(names));
    sub.add_option("--set", set, "Classifier parameter key=value (repeatable)");
}

}  // namespace gs::app
