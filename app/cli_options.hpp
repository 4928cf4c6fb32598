#pragma once
// Options several subcommands share, declared, checked and applied in one place so they mean the
// same everywhere:
//   --calibration FILE   replay, eval, odometry, record: a calibration JSON instead of the
//                        dataset's (flight.json's or the camera default); checked when parsed
//                        (a missing or malformed file is refused before any work)
//   --fps N              replay, eval, odometry, dataset info/import-thesis: the frame rate of a
//                        thesis-style image folder (which has no timestamps)
//   --classifier, --set  replay, eval: the obstacle classifier and its parameter overrides

#include "drone/core/camera_calibration.hpp"
#include "drone/core/expected.hpp"
#include "drone/dataset/dataset.hpp"
#include "drone/sim/realism.hpp"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <initializer_list>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace gs::app {

// --calibration FILE: a camera calibration JSON (flight.json's calibration object, or what
// `ardrone-gs calibrate` writes), used instead of `instead_of`. The file is loaded when the option
// is parsed: a missing or malformed one is an option error naming the file and the problem.
CLI::Option* add_calibration_option(CLI::App& sub, std::string& file,
                                    const std::string& instead_of);

// --fps N: the frame rate of a thesis-style image folder (docs/dataset.md says 25 unless told).
// Checked as a number in (0, 1000]; 0 in `fps` means not given.
CLI::Option* add_thesis_fps_option(CLI::App& sub, double& fps);
// The value to pass on: nullopt when --fps was not given.
inline std::optional<double> given_fps(double fps) {
    return fps > 0 ? std::optional<double>(fps) : std::nullopt;
}

// What a headless run over a dataset is told about its input: --calibration and --fps.
struct DatasetInputOptions {
    std::string calibration;  // empty: the dataset's own
    double fps = 0;           // 0: not given
};
// Adds --calibration and --fps (above) to `sub`.
void add_dataset_input_options(CLI::App& sub, DatasetInputOptions& o,
                               const std::string& calibration_instead_of);
// A dataset directory or thesis-style folder, opened as the options say; the error names the
// path and the problem.
[[nodiscard]] Expected<dataset::Dataset, std::string> open_input_dataset(
    const std::string& path, const DatasetInputOptions& o);
// The calibration the run uses for `d`'s frames: --calibration's file scaled to the frame size,
// else the dataset's.
[[nodiscard]] Expected<CameraCalibration, std::string> input_calibration(
    const dataset::Dataset& d, const DatasetInputOptions& o);

// --realism and its Realism group (generate, eval-assist): the real-camera preset
// (RealismOptions::real_camera()) or nothing, then each effect by name (--rolling-shutter-ms ...).
struct RealismCli {
    bool preset = false;
    std::map<std::string, double> effect;  // given one by one, by flight.json key
};
void add_realism_options(CLI::App& sub, RealismCli& r, const std::string& preset_help);
// The options as given, checked: the error names the bad value.
[[nodiscard]] Expected<sim::RealismOptions, std::string> realism_options(const RealismCli& r);

// Checks of paths and numbers, applied when the options are parsed (before any work), each
// failing with one line that says what was expected:
// An existing regular file to read (a directory, a FIFO or a device is refused: reading a FIFO
// would block, and a directory has no size).
CLI::Validator regular_file();
// An image, an image folder or a dataset folder: a regular file or a directory.
CLI::Validator file_or_directory();
// A file to write: its folder exists; the path is not a directory.
CLI::Validator output_file();
// A directory to write into (created when missing): not an existing file, and its nearest
// existing parent is a directory.
CLI::Validator output_directory();
// A number in [lo, hi] (hi = infinity: no upper bound); the message prints the bounds short.
CLI::Validator number_in(double lo, double hi, const std::string& what);
// A non-negative integer written in decimal digits ("-1" would wrap to 2^64 - 1).
CLI::Validator unsigned_integer();
// The outputs of a run may go into `dir` when it is missing, empty, or holds nothing but files
// named in `own` (a previous run's outputs); otherwise an error unless `force`.
[[nodiscard]] std::optional<std::string> check_output_dir(const std::filesystem::path& dir,
                                                          std::initializer_list<const char*> own,
                                                          bool force);

// --jobs,-j N: how many flights a batch command (eval, generate --suite) works on at once; the
// default is every core this process may run on (its CPU affinity, which taskset, cgroups and
// batch schedulers such as Slurm restrict), so a job array's tasks use what they were given.
int usable_cores();
CLI::Option* add_jobs_option(CLI::App& sub, int& jobs, const std::string& what);

// --shard K/N: the K-th of N parts of a batch (K from 1 to N), for splitting it across
// processes or machines: the part holds the flights whose index in the batch's sorted list,
// counted from 0, is K-1 modulo N ("every N-th flight"). {1, 1} is the whole batch.
struct Shard {
    int k = 1, n = 1;
    bool whole() const { return n == 1; }
    bool holds(std::size_t index) const {
        return static_cast<int>(index % static_cast<std::size_t>(n)) == k - 1;
    }
};
CLI::Option* add_shard_option(CLI::App& sub, Shard& shard, const std::string& what);

// --classifier NAME (thesis or flow) and --set key=value (repeatable).
void add_classifier_options(CLI::App& sub, std::string& classifier, std::vector<std::string>& set);

}  // namespace gs::app
