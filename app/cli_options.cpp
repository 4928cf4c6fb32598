#include "app/cli_options.hpp"

#include <algorithm>

#include "app/replay_outputs.hpp"
#include "app/replay_run.hpp"
#include "vision/classifier.hpp"

#include <sched.h>
#include <sys/stat.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <thread>

namespace gs::app {

CLI::Option* add_calibration_option(CLI::App& sub, std::string& file,
                                    const std::string& instead_of) {
    const CLI::Validator loads(
        [](std::string& path) -> std::string {
            auto c = load_calibration_file(path);
            if (!c) return to_string(c.error());
            return {};
        },
        "", "calibration file");  // read_text_file refuses directories and FIFOs unopened
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

namespace {
namespace fs = std::filesystem;

// What a path is, by stat (following symlinks): a FIFO answers as itself, without being opened.
std::string kind_of(const std::string& path, struct stat& st) {
    if (::stat(path.c_str(), &st) != 0) return "missing";
    if (S_ISREG(st.st_mode)) return "file";
    if (S_ISDIR(st.st_mode)) return "directory";
    if (S_ISFIFO(st.st_mode)) return "FIFO";
    if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) return "device";
    if (S_ISSOCK(st.st_mode)) return "socket";
    return "special file";
}

std::string short_number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

}  // namespace

CLI::Validator regular_file() {
    return CLI::Validator(
        [](std::string& path) -> std::string {
            struct stat st {};
            const std::string k = kind_of(path, st);
            if (k == "missing") return "cannot open " + path + ": no such file";
            if (k != "file") return path + " is a " + k + ", not a regular file";
            return {};
        },
        "FILE", "regular file");
}

CLI::Validator file_or_directory() {
    return CLI::Validator(
        [](std::string& path) -> std::string {
            struct stat st {};
            const std::string k = kind_of(path, st);
            if (k == "missing") return path + ": no such file or directory";
            if (k != "file" && k != "directory")
                return path + " is a " + k + ", not an image file or a folder";
            return {};
        },
        "PATH", "file or directory");
}

CLI::Validator output_file() {
    return CLI::Validator(
        [](std::string& path) -> std::string {
            struct stat st {};
            const std::string k = kind_of(path, st);
            if (k == "directory") return path + " is a directory, not a file to write";
            if (k != "missing" && k != "file") return path + " is a " + k + ", not a file to write";
            fs::path parent = fs::path(path).parent_path();
            if (parent.empty()) parent = ".";
            const std::string pk = kind_of(parent.string(), st);
            if (pk != "directory")
                return "cannot write " + path + ": " + parent.string() +
                       (pk == "missing" ? " does not exist" : " is not a directory");
            return {};
        },
        "FILE", "output file");
}

CLI::Validator output_directory() {
    return CLI::Validator(
        [](std::string& path) -> std::string {
            struct stat st {};
            const std::string k = kind_of(path, st);
            if (k == "directory") return {};
            if (k != "missing") return path + " is a " + k + ", not a directory";
            // Created with its missing parents: the nearest existing one must be a directory.
            fs::path p = fs::absolute(fs::path(path)).parent_path();
            while (!p.empty() && kind_of(p.string(), st) == "missing" && p != p.root_path())
                p = p.parent_path();
            if (kind_of(p.string(), st) != "directory")
                return "cannot create " + path + ": " + p.string() + " is not a directory";
            return {};
        },
        "DIR", "output directory");
}

CLI::Validator number_in(double lo, double hi, const std::string& what) {
    const std::string range = std::isinf(hi)
                                  ? ">= " + short_number(lo)
                                  : "in [" + short_number(lo) + ", " + short_number(hi) + "]";
    return CLI::Validator(
        [lo, hi, range, what](std::string& text) -> std::string {
            double v = 0;
            const char* end = text.data() + text.size();
            auto [p, ec] = std::from_chars(text.data(), end, v);
            if (ec != std::errc() || p != end || !std::isfinite(v) || v < lo || v > hi)
                return "expected " + what + " " + range + ", got '" + text + "'";
            return {};
        },
        "", what);
}

CLI::Validator unsigned_integer() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            std::uint64_t v = 0;
            const char* end = text.data() + text.size();
            auto [p, ec] = std::from_chars(text.data(), end, v);
            if (text.empty() || ec != std::errc() || p != end)
                return "expected an integer from 0 to 18446744073709551615, got '" + text + "'";
            return {};
        },
        "", "unsigned integer");
}

int usable_cores() {
    cpu_set_t set;
    CPU_ZERO(&set);
    if (::sched_getaffinity(0, sizeof set, &set) == 0) {
        const int n = CPU_COUNT(&set);
        if (n > 0) return n;
    }
    return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

CLI::Option* add_jobs_option(CLI::App& sub, int& jobs, const std::string& what) {
    jobs = usable_cores();
    return sub
        .add_option("--jobs,-j", jobs,
                    what + " in parallel (default: every core this process may use, " +
                        std::to_string(jobs) + " here)")
        ->check(CLI::Range(1, 256));
}

CLI::Option* add_shard_option(CLI::App& sub, Shard& shard, const std::string& what) {
    return sub
        .add_option_function<std::string>(
            "--shard",
            [&shard](const std::string& text) {
                int k = 0, n = 0;
                const char* b = text.data();
                const char* e = b + text.size();
                const auto slash = text.find('/');
                auto [p1, ec1] = std::from_chars(b, b + std::min(slash, text.size()), k);
                bool ok = slash != std::string::npos && ec1 == std::errc() && p1 == b + slash;
                if (ok) {
                    auto [p2, ec2] = std::from_chars(b + slash + 1, e, n);
                    ok = ec2 == std::errc() && p2 == e && n >= 1 && n <= 100000 && k >= 1 && k <= n;
                }
                if (!ok)
                    throw CLI::ValidationError(
                        "--shard", "expected K/N with 1 <= K <= N <= 100000, got '" + text + "'");
                shard = Shard{k, n};
            },
            what)
        ->type_name("K/N");
}

std::optional<std::string> check_output_dir(const fs::path& dir,
                                            std::initializer_list<const char*> own, bool force) {
    std::error_code ec;
    if (force || !fs::is_directory(dir, ec)) return std::nullopt;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        bool ours = false;
        for (const char* o : own) ours = ours || name == o;
        if (!ours)
            return dir.string() + " already holds " + name +
                   ", which is not an output of this command: give an empty or new folder, or "
                   "--force to write into it anyway";
    }
    if (ec) return "cannot read " + dir.string() + ": " + ec.message();
    return std::nullopt;
}

void add_classifier_options(CLI::App& sub, std::string& classifier, std::vector<std::string>& set) {
    std::vector<std::string> names;
    for (auto n : vision::classifier_names()) names.emplace_back(n);
    sub.add_option("--classifier", classifier, "Obstacle classifier: thesis or flow")
        ->capture_default_str()
        ->check(CLI::IsMember(names));
    sub.add_option("--set", set,
                   "Classifier parameter key=value (repeatable; `ardrone-gs params` lists every "
                   "key with its default and range)");
}

void add_realism_options(CLI::App& sub, RealismCli& r, const std::string& preset_help) {
    sub.add_flag("--realism", r.preset, preset_help);
    for (const sim::RealismField& f : sim::realism_fields()) {
        std::string flag = std::string("--") + f.name;
        std::replace(flag.begin(), flag.end(), '_', '-');
        const std::string name = f.name;
        sub.add_option_function<double>(
               flag, [&r, name](double v) { r.effect[name] = v; }, f.help)
            ->check(number_in(f.lo, f.hi, f.name))
            ->group("Realism");
    }
}

Expected<sim::RealismOptions, std::string> realism_options(const RealismCli& r) {
    sim::RealismOptions o = r.preset ? sim::RealismOptions::real_camera() : sim::RealismOptions{};
    for (const sim::RealismField& f : sim::realism_fields())
        if (auto it = r.effect.find(f.name); it != r.effect.end()) o.*f.member = it->second;
    if (auto e = o.check()) return Unexpected(*e);
    return o;
}

}  // namespace gs::app
