// `ardrone-gs dataset ...`: looking at and converting flight datasets (docs/dataset.md).
//   dataset info DATASET                 what is in it (frames, rate, camera, labels, warnings)
//   dataset export-thesis DATASET OUT    the thesis' layout: one image per frame + imu.txt
//   dataset import-thesis FOLDER OUT     a thesis-style folder into a dataset directory
//   dataset frames DATASET OUT [--every N] [--from A --to B]   frames as PNG files
//   dataset import-video FILE --out DIR [--fps N]  any video file (no navdata) into a dataset
//   dataset check-raw DATASET            raw/ replayed through the protocol parsers = frames.csv?
#include "app/cli_options.hpp"
#include "app/command.hpp"
#include "app/replay_outputs.hpp"
#include "drone/dataset/raw_replay.hpp"
#include "drone/dataset/thesis.hpp"
#include "drone/dataset/video_frames.hpp"
#include "drone/dataset/video_import.hpp"
#include "drone/dataset/writer.hpp"

#include <opencv2/imgcodecs.hpp>

#include <unistd.h>
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>

namespace gs::app::cmd_dataset {
namespace {
namespace fs = std::filesystem;

struct Opts {
    std::string in, out;
    double fps = 0;  // --fps (thesis-style folders); 0: not given
    std::int64_t every = 1, from = 0, to = -1;
    // import-video
    std::string mode = "auto";
    std::string camera = "front";
    std::string calibration;
    int bitrate_kbps = 6000;
    std::int64_t max_frames = -1;
    bool quiet = false;
};

int info(const Opts& o) {
    auto d = open_any_dataset(o.in, given_fps(o.fps));
    if (!d) throw fail(d.error());
    const dataset::DatasetInfo& i = d->info();
    const double dur =
        d->frames().empty() ? 0.0 : static_cast<double>(d->frames().back().nav.t_ns) * 1e-9;
    std::cout << o.in << ": " << to_string(i.camera) << " camera, " << i.width << "x" << i.height
              << ", " << fixed(i.fps, 2) << " fps, " << d->frame_count() << " frames ("
              << fixed(dur, 2) << " s)\n"
              << "  pixels: "
              << (d->video_path()
                      ? i.video + " (" + std::to_string(d->video_units().size()) + " access units)"
                      : std::string(i.images + "/ (" + std::to_string(d->image_files().size()) +
                                    " images)"))
              << "\n  calibration: "
              << (d->calibration_is_default() ? "camera default (assets)" : "flight.json") << " fx "
              << fixed(d->calibration().fx, 2) << " cx " << fixed(d->calibration().cx, 2) << " cy "
              << fixed(d->calibration().cy, 2) << "\n  navdata.csv: "
              << (d->has_navdata() ? std::to_string(d->navdata().size()) + " samples" : "absent")
              << "\n  raw/: " << (d->raw_dir() ? "present" : "absent") << "\n  labels: "
              << (d->labels() ? to_string(d->labels()->scenario) : std::string("none"));
    if (d->label_rows()) std::cout << ", " << d->label_rows()->size() << " rows in labels.csv";
    std::cout << "\n  source: " << (i.source.empty() ? "-" : i.source) << '\n';
    for (const auto& w : d->warnings()) std::cout << "  warning: " << w << '\n';
    return 0;
}

int export_thesis_cmd(const Opts& o) {
    auto d = open_any_dataset(o.in);
    if (!d) throw fail(d.error());
    auto frames = dataset::open_frames(*d);
    if (!frames) throw fail(o.in + ": " + to_string(frames.error()));
    if (auto e = dataset::export_thesis(*d, **frames, o.out)) throw fail(to_string(*e));
    std::cout << "wrote " << d->frame_count() << " images, imu.txt, imu_extra.csv and imu_meta.json"
              << (d->labels() || d->label_rows() ? " and the labels" : "") << " to " << o.out
              << '\n';
    return 0;
}

int import_thesis_cmd(const Opts& o) {
    dataset::ThesisImportOptions to;
    to.fps = given_fps(o.fps);
    auto d = dataset::import_thesis(o.in, o.out, to);
    if (!d) throw fail(to_string(d.error()));
    std::cout << "imported " << d->frame_count() << " frames at " << fixed(d->info().fps, 2)
              << " fps into " << o.out << '\n';
    return 0;
}

int frames_cmd(const Opts& o) {
    auto d = open_any_dataset(o.in);
    if (!d) throw fail(d.error());
    // The range is checked against the dataset before any frame is decoded or folder created.
    const std::int64_t count = d->frame_count();
    if (count == 0) throw fail(o.in + ": the dataset has no frames");
    if (o.from > count - 1)
        throw fail("--from " + std::to_string(o.from) + " is past the last frame (" +
                   std::to_string(count - 1) + ")");
    if (o.to > count - 1)
        throw fail("--to " + std::to_string(o.to) + " is past the last frame (" +
                   std::to_string(count - 1) + ")");
    if (o.to >= 0 && o.to < o.from)
        throw fail("--to " + std::to_string(o.to) + " is before --from " + std::to_string(o.from));
    const std::int64_t last = o.to < 0 ? count - 1 : o.to;
    auto frames = dataset::open_frames(*d);
    if (!frames) throw fail(o.in + ": " + to_string(frames.error()));
    std::error_code ec;
    fs::create_directories(o.out, ec);
    if (ec) throw fail("cannot create " + o.out + ": " + ec.message());
    cv::Mat img;
    std::int64_t n = 0;
    for (std::int64_t i = std::max<std::int64_t>(0, o.from); i <= last;
         i += std::max<std::int64_t>(1, o.every)) {
        if (auto e = (*frames)->read(i, img))
            throw fail("frame " + std::to_string(i) + ": " + to_string(*e));
        char name[32];
        std::snprintf(name, sizeof name, "%06lld.png", static_cast<long long>(i));
        if (!cv::imwrite((fs::path(o.out) / name).string(), img))
            throw fail("cannot write " + (fs::path(o.out) / name).string());
        ++n;
    }
    std::cout << "wrote " << n << " frames to " << o.out << '\n';
    return 0;
}

int import_video_cmd(const Opts& o) {
    using dataset::VideoImportMode;
    dataset::VideoImportOptions vo;
    vo.mode = o.mode == "copy"     ? VideoImportMode::Copy
              : o.mode == "encode" ? VideoImportMode::Encode
                                   : VideoImportMode::Auto;
    vo.fps = o.fps;
    vo.camera = o.camera == "bottom" ? CameraId::Bottom : CameraId::Front;
    vo.bitrate_bps = o.bitrate_kbps * 1000;
    vo.max_frames = o.max_frames;
    if (!o.calibration.empty()) {
        auto c = load_calibration_file(o.calibration);
        if (!c) throw fail(to_string(c.error()));
        vo.calibration = *c;
    }
    const bool tty = !o.quiet && ::isatty(STDERR_FILENO) == 1;
    if (tty)
        vo.progress = [](std::int64_t n) {
            if (n % 25 == 0) std::cerr << "\rimport-video: " << n << " frames" << std::flush;
        };
    auto r = dataset::import_video(o.in, o.out, vo);
    if (tty) std::cerr << "\r\033[K" << std::flush;
    if (!r) throw fail(r.error());
    if (vo.calibration && (vo.calibration->width != 0 && (vo.calibration->width != r->width ||
                                                          vo.calibration->height != r->height)))
        std::cerr << "ardrone-gs: note: the calibration is for " << vo.calibration->width << "x"
                  << vo.calibration->height << ", the frames are " << r->width << "x" << r->height
                  << '\n';
    if (!o.quiet)
        std::cout << "imported " << r->frames << " frames (" << r->width << "x" << r->height << ", "
                  << fixed(r->fps, 2) << " fps, " << r->codec << ", "
                  << (r->copied ? "access units copied" : "encoded again as H.264") << ") into "
                  << o.out << "; no navdata: attitude and velocity unknown\n";
    if (!o.quiet && r->skipped_before_keyframe > 0)
        std::cout << "  " << r->skipped_before_keyframe
                  << " access units before the first IDR could not be decoded and were left out\n";
    if (!o.quiet && r->decode_errors > 0)
        std::cout << "  " << r->decode_errors << " packets the decoder refused\n";
    if (!o.quiet && r->untimed)
        std::cout << "  the file has no frame times: frame n at n / " << fixed(r->fps, 2)
                  << " s (give --fps if the camera ran at another rate)\n";
    if (!o.quiet && r->timestamp_repairs > 0)
        std::cout << "  " << r->timestamp_repairs
                  << " frames without an increasing timestamp were placed one frame interval on\n";
    return 0;
}

// frames.csv's row for `r` as the writer writes it (docs/dataset.md), the ground-truth columns
// left empty (raw/ has no ground truth): what a replay of raw/ must reproduce, as the file says it.
std::string frame_text(dataset::FrameRow r) {
    r.gt = {};
    std::string s = dataset::frames_csv_row(r);
    s.pop_back();  // the newline
    return s;
}

// docs/dataset.md "raw/": replaying raw/ through the protocol parsers (the link's navdata rule and
// video receiver) must reproduce frames.csv. Prints what it read (with every warning: a file cut
// short is replayed up to the cut), the frame counts, and exits 0 only when every row matches.
int check_raw_cmd(const Opts& o) {
    auto d = dataset::Dataset::open(o.in);
    if (!d) throw fail(o.in + ": " + to_string(d.error()));
    if (!d->raw_dir())
        throw fail(o.in + ": no raw/ folder (recordings write one): nothing to replay");
    std::vector<std::string> warnings;
    auto dec = dataset::make_protocol_replay_decoders();
    auto rows = dataset::replay_raw(*d->raw_dir(), dec, &warnings);
    if (!rows) throw fail(o.in + ": " + to_string(rows.error()));
    const std::vector<dataset::FrameRow>& frames = d->frames();
    std::cout << o.in << ": raw/ replayed through the protocol parsers\n";
    for (const auto& w : d->warnings()) std::cout << "  warning: " << w << '\n';
    for (const auto& w : warnings) std::cout << "  warning: " << w << '\n';
    std::cout << "  frames: " << rows->size() << " replayed, " << frames.size()
              << " in frames.csv\n";
    const std::size_t n = std::min(rows->size(), frames.size());
    std::size_t same = 0;
    std::string difference;
    for (; same < n; ++same) {
        const std::string want = frame_text(frames[same]), got = frame_text((*rows)[same]);
        if (want != got) {
            difference = "frame " + std::to_string(same) + ": frames.csv has '" + want +
                         "', the replay gives '" + got + "'";
            break;
        }
    }
    if (difference.empty() && rows->size() == frames.size()) {
        std::cout << "  every frame as in frames.csv (index, capture time, attitude, velocity, "
                     "altitude)\n";
        return 0;
    }
    std::cout << "  the first " << same << " frames as in frames.csv\n";
    if (difference.empty())
        difference = rows->size() < frames.size()
                         ? std::to_string(frames.size() - rows->size()) +
                               " frames.csv rows after the replay's last frame"
                         : std::to_string(rows->size() - frames.size()) +
                               " replayed frames after frames.csv's last row";
    if (!warnings.empty()) difference += " (raw/ was cut short: see the warnings)";
    throw fail(o.in + ": raw/ does not reproduce frames.csv: " + difference);
}

CommandRegistration reg_info(
    70, "dataset", "Look at and convert flight datasets (docs/dataset.md)", [](CLI::App& parent) {
        auto o = std::make_shared<Opts>();
        auto* c = parent.add_subcommand("info", "What a dataset holds");
        c->add_option("DATASET", o->in, "Dataset or thesis-style folder")->required();
        add_thesis_fps_option(*c, o->fps);
        set_action(*c, [o] { return info(*o); });
    });

CommandRegistration reg_export(
    71, "dataset", "Look at and convert flight datasets (docs/dataset.md)", [](CLI::App& parent) {
        auto o = std::make_shared<Opts>();
        auto* c = parent.add_subcommand(
            "export-thesis",
            "Write the thesis' layout: 000000.png ... + imu.txt (roll pitch yaw vx vy)");
        c->footer(
            "The IMU lines hold only roll pitch yaw vx vy, so the rest travels in side files the "
            "import reads when present: imu_extra.csv (per image, frames.csv's columns: frame, "
            "t_ms, vz_mps, altitude_m, gt_*), imu_meta.json (fps, camera, calibration as in "
            "flight.json) and the labels (labels.json, labels.csv). Import gives back the same "
            "flight, so a replay decides the same.");
        c->add_option("DATASET", o->in, "Dataset directory")->required();
        c->add_option("OUT", o->out, "Folder to create (new or empty)")->required();
        set_action(*c, [o] { return export_thesis_cmd(*o); });
    });

CommandRegistration reg_import(
    72, "dataset", "Look at and convert flight datasets (docs/dataset.md)", [](CLI::App& parent) {
        auto o = std::make_shared<Opts>();
        auto* c = parent.add_subcommand(
            "import-thesis", "Turn a thesis-style image folder into a dataset directory");
        c->add_option("FOLDER", o->in, "Images + one IMU text line per image")->required();
        c->add_option("OUT", o->out, "Dataset directory to create (new or empty)")->required();
        add_thesis_fps_option(*c, o->fps);
        set_action(*c, [o] { return import_thesis_cmd(*o); });
    });

CommandRegistration reg_frames(
    73, "dataset", "Look at and convert flight datasets (docs/dataset.md)", [](CLI::App& parent) {
        auto o = std::make_shared<Opts>();
        auto* c = parent.add_subcommand("frames", "Write frames as PNG files (NNNNNN.png)");
        c->add_option("DATASET", o->in, "Dataset or thesis-style folder")->required();
        c->add_option("OUT", o->out, "Folder for the PNGs")->required();
        c->add_option("--every", o->every, "Every Nth frame")
            ->check(number_in(1, 1e9, "a frame step"));
        c->add_option("--from", o->from, "First frame")->check(number_in(0, 1e12, "a frame index"));
        c->add_option("--to", o->to, "Last frame (default: the last)")
            ->check(number_in(0, 1e12, "a frame index"));
        set_action(*c, [o] { return frames_cmd(*o); });
    });

CommandRegistration reg_import_video(
    74, "dataset", "Look at and convert flight datasets (docs/dataset.md)", [](CLI::App& parent) {
        auto o = std::make_shared<Opts>();
        auto* c = parent.add_subcommand(
            "import-video", "Turn any video file (MP4, AVI, MKV, raw H.264 ...) into a dataset");
        c->footer(
            "The dataset has no navdata: frames.csv holds the frame times and empty (unknown) "
            "attitude, velocity and altitude, which the classifiers treat as such. An H.264 "
            "stream without B-frames (the AR.Drone's) is copied bit for bit; other video is "
            "decoded and encoded again as H.264 (Baseline, IDR every 15 frames). Frame times are "
            "the container's unless --fps is given. Add labels.json / labels.csv "
            "(docs/dataset.md) by hand to evaluate it.");
        c->add_option("FILE", o->in, "Video file")->required()->check(CLI::ExistingFile);
        c->add_option("--out,-o", o->out, "Dataset directory to create (new or empty)")->required();
        c->add_option("--fps", o->fps,
                      "Frame rate: frame n at n / FPS s (default: the container's timestamps)")
            ->type_name("FPS")
            ->check(CLI::Range(0.001, 1000.0));
        c->add_option("--video", o->mode, "copy, encode, or auto (copy when possible)")
            ->capture_default_str()
            ->check(CLI::IsMember({"auto", "copy", "encode"}));
        c->add_option("--bitrate", o->bitrate_kbps, "H.264 bitrate in kbit/s when encoding")
            ->capture_default_str()
            ->check(CLI::Range(100, 100000));
        c->add_option("--camera", o->camera, "Which camera filmed it (front or bottom)")
            ->capture_default_str()
            ->check(CLI::IsMember({"front", "bottom"}));
        add_calibration_option(*c, o->calibration, "the camera default (written to flight.json)");
        c->add_option("--max-frames", o->max_frames, "Import at most this many frames")
            ->check(CLI::NonNegativeNumber);
        c->add_flag("--quiet,-q", o->quiet, "No summary line");
        set_action(*c, [o] { return import_video_cmd(*o); });
    });

CommandRegistration reg_check_raw(
    75, "dataset", "Look at and convert flight datasets (docs/dataset.md)", [](CLI::App& parent) {
        auto o = std::make_shared<Opts>();
        auto* c = parent.add_subcommand(
            "check-raw", "Replay raw/ through the protocol parsers and check it gives frames.csv");
        c->footer(
            "A recording keeps what crossed the wire in raw/ (docs/dataset.md): every navdata "
            "datagram, the video stream with its connections and receive times. Replayed through "
            "the link's own navdata rule and video receiver, it must give frames.csv row for row "
            "(index, capture time, attitude, velocity, altitude). Prints the frame counts and "
            "every warning (a raw/ file cut short is replayed up to the cut); exits 1 at the "
            "first row that differs or when the counts differ.");
        c->add_option("DATASET", o->in, "Recorded dataset directory (with raw/)")
            ->required()
            ->check(CLI::ExistingDirectory);
        set_action(*c, [o] { return check_raw_cmd(*o); });
    });

}  // namespace
}  // namespace gs::app::cmd_dataset
