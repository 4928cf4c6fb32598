// `ardrone-gs calibrate IMAGE|FOLDER|DATASET... --board 9x6 --square 0.05 [--out FILE]`: finds the
// chessboard in each image, calibrates pinhole + k1 k2 p1 p2 k3 (vision/calibration), rejects
// views whose error stands out, and reports per-image and overall error, the parameters with
// their uncertainty and the coverage of the field of view. Writes flight.json's calibration shape.
#include "app/cli_options.hpp"
#include "app/command.hpp"
#include "drone/core/camera_calibration.hpp"
#include "drone/dataset/dataset.hpp"
#include "drone/dataset/video_frames.hpp"
#include "vision/calibration.hpp"

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

namespace gs::app::cmd_calibrate {
namespace {

namespace fs = std::filesystem;
using namespace gs::vision;

struct Opts {
    std::vector<std::string> inputs;
    std::string board = "9x6";
    double square_m = 0;
    std::string out;
    std::string camera;
    int step = 1;
    bool sb = false;
    bool fix_k3 = false;
};

// A dataset's frames, read through the dataset reader (the path rules of docs/dataset.md apply) and
// its FrameStore: video.h264 decoded, else the frames/ images.
struct DatasetFrames {
    dataset::Dataset dataset;
    std::unique_ptr<dataset::FrameStore> store;
    std::int64_t last = -1;  // last frame read (video decodes forward from it)
};

struct Input {
    std::string path;                       // an image file, or the dataset's directory
    std::string name;                       // as shown in the report
    std::shared_ptr<DatasetFrames> frames;  // set: frame `index` of that dataset
    std::int64_t index = -1;
};

// The input's pixels (BGR); empty with `error` set when they cannot be read.
cv::Mat load_input(const Input& in, std::string& error) {
    if (!in.frames) {
        cv::Mat img = cv::imread(in.path, cv::IMREAD_COLOR);
        if (img.empty()) error = "not an image OpenCV can read";
        return img;
    }
    DatasetFrames& f = *in.frames;
    cv::Mat img;
    // Video: decode the frames in between in order (one access unit each) rather than going back
    // to the last IDR for every frame taken.
    if (f.dataset.video_path() && in.index > f.last + 1 && f.last >= 0) {
        for (std::int64_t i = f.last + 1; i < in.index; ++i) (void)f.store->read(i, img);
    }
    f.last = in.index;
    if (auto e = f.store->read(in.index, img)) {
        error = to_string(*e);
        return {};
    }
    return img;
}

bool is_image_file(const fs::path& p) {
    std::string ext = p.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    for (const char* e :
         {".jpg", ".jpeg", ".png", ".bmp", ".pgm", ".ppm", ".pnm", ".tif", ".tiff", ".webp"}) {
        if (ext == e) return true;
    }
    return false;
}

// Images of a folder, sorted by name, every `step`-th.
std::vector<Input> folder_images(const fs::path& dir, int step) {
    std::vector<fs::path> files;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        if (e.is_regular_file(ec) && is_image_file(e.path())) files.push_back(e.path());
    }
    if (ec) throw fail("cannot list " + dir.string() + ": " + ec.message());
    std::sort(files.begin(), files.end());
    std::vector<Input> out;
    for (std::size_t i = 0; i < files.size(); i += static_cast<std::size_t>(step)) {
        out.push_back({files[i].string(), files[i].filename().string(), nullptr, -1});
    }
    return out;
}

// A recorded dataset (docs/dataset.md), opened by the dataset reader: every `step`-th frame, from
// video.h264 when it has one (the source of truth), else from its image folder.
std::vector<Input> dataset_frames(const fs::path& dir, int step, std::string& camera) {
    auto d = dataset::Dataset::open(dir);
    if (!d) throw fail(dir.string() + ": " + to_string(d.error()));
    auto store = dataset::open_frames(*d);
    if (!store) throw fail(dir.string() + ": " + to_string(store.error()));
    if (camera.empty()) camera = to_string(d->info().camera);
    auto frames = std::make_shared<DatasetFrames>(DatasetFrames{std::move(*d), std::move(*store)});
    const dataset::Dataset& ds = frames->dataset;
    std::vector<Input> out;
    for (std::int64_t i = 0; i < ds.frame_count(); i += step) {
        std::string name;
        if (ds.video_path()) {
            name = ds.info().video + " frame " + std::to_string(i);
        } else {
            name = ds.info().images + "/" +
                   ds.image_files()[static_cast<std::size_t>(i)].filename().string();
        }
        out.push_back({dir.string(), std::move(name), frames, i});
    }
    return out;
}

std::vector<Input> collect_inputs(const Opts& o, std::string& camera) {
    std::vector<Input> all;
    for (const auto& arg : o.inputs) {
        const fs::path p(arg);
        std::error_code ec;
        if (fs::is_directory(p, ec)) {
            auto imgs = fs::exists(fs::symlink_status(p / "flight.json", ec))
                            ? dataset_frames(p, o.step, camera)
                            : folder_images(p, o.step);
            if (imgs.empty()) throw fail("no images (jpg, png, ...) in " + arg);
            all.insert(all.end(), imgs.begin(), imgs.end());
        } else if (fs::exists(p, ec)) {
            all.push_back({arg, p.filename().string(), nullptr, -1});
        } else {
            throw fail(arg + ": no such file or folder");
        }
    }
    return all;
}

std::string fixed(double v, int decimals) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return buf;
}

std::string shortest(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

struct ImageRow {
    Input input;
    FrameStatus status = FrameStatus::NotFound;
    bool unreadable = false;
    int view = -1;  // index into the session's views when kept
};

void print_coverage(const CoverageMap& c) {
    std::cout << "  coverage map (" << c.grid_cols() << "x" << c.grid_rows()
              << " cells, digit = boards covering the cell):\n";
    for (int r = 0; r < c.grid_rows(); ++r) {
        std::cout << "    |";
        for (int col = 0; col < c.grid_cols(); ++col) {
            const int n = c.count(col, r);
            std::cout << (n == 0 ? '.' : n > 9 ? '+' : static_cast<char>('0' + n));
        }
        std::cout << "|\n";
    }
}

void run(const Opts& o) {
    const auto size = parse_board_size(o.board);
    if (!size) {
        throw fail(
            "--board must count inner corners as COLSxROWS, 3..100 each, e.g. 9x6 for a "
            "board of 10x7 squares; got '" +
            o.board + "'");
    }
    if (!(o.square_m > 0) || !std::isfinite(o.square_m)) {
        throw fail("--square must be the square size in metres, > 0 (e.g. 0.05)");
    }
    if (o.square_m > 2.0) {
        throw fail("--square " + shortest(o.square_m) +
                   " m is no printable chessboard square; give metres (50 mm = 0.05)");
    }
    if (o.step < 1) throw fail("--step must be >= 1");
    const BoardSpec board{size->width, size->height, o.square_m};

    std::string camera = o.camera;
    const std::vector<Input> inputs = collect_inputs(o, camera);
    if (inputs.empty()) throw fail("no images given");

    SessionOptions so;
    so.detect.sb_fallback = o.sb;
    so.calibration.fix_k3 = o.fix_k3;
    so.recalibrate_on_add = false;  // once at the end
    CalibrationSession session(board, so);

    std::cout << "Calibrating from " << inputs.size() << " image(s), board " << board.cols << "x"
              << board.rows << " inner corners, " << fixed(board.square_m * 1000, 1)
              << " mm squares\n";
    const auto t_detect = std::chrono::steady_clock::now();
    std::vector<ImageRow> rows;
    std::size_t unreadable = 0, not_found = 0, blurry = 0;
    const int width = static_cast<int>(std::to_string(inputs.size()).size());
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        ImageRow row{inputs[i]};
        const auto t0 = std::chrono::steady_clock::now();
        std::string read_error;
        const cv::Mat img = load_input(inputs[i], read_error);
        std::printf("[%*zu/%zu] %-28s ", width, i + 1, inputs.size(), inputs[i].name.c_str());
        if (img.empty()) {
            row.unreadable = true;
            ++unreadable;
            std::printf("%s, skipped\n", read_error.c_str());
            rows.push_back(row);
            continue;
        }
        const ViewResult f = session.add_frame(img, /*require_new_coverage=*/false);
        row.status = f.status;
        if (f.status == FrameStatus::SizeMismatch) {
            std::printf("%dx%d\n", img.cols, img.rows);
            std::fflush(stdout);
            const cv::Size first = *session.image_size();
            throw fail(inputs[i].name + " is " + std::to_string(img.cols) + "x" +
                       std::to_string(img.rows) + " but the earlier images are " +
                       std::to_string(first.width) + "x" + std::to_string(first.height) +
                       ": a calibration holds for one image size, calibrate each size separately");
        }
        if (f.accepted()) {
            row.view = static_cast<int>(session.view_count()) - 1;
            std::printf("board found, sharpness %.1f px, +%d cells (%.0f ms)\n",
                        f.detection.sharpness_px, f.new_cells, ms_since(t0));
        } else {
            if (f.status == FrameStatus::Blurry) {
                ++blurry;
                std::printf("board blurry (edge width %.1f px > %.1f), skipped\n",
                            f.detection.sharpness_px, so.detect.max_blur_px);
            } else {
                ++not_found;
                std::printf(
                    "board not found: no whole %dx%d board (partly out of view, covered, or "
                    "another size?) (%.0f ms)\n",
                    board.cols, board.rows, ms_since(t0));
            }
        }
        rows.push_back(row);
    }
    const double detect_s = ms_since(t_detect) / 1000;
    std::fflush(stdout);

    const std::size_t found = session.view_count();
    const std::string board_hint =
        "Check --board: it counts inner corners (a board of 10x7 squares is 9x6), and the whole "
        "board must be in view" +
        std::string(o.sb ? "" : "; --sb tries a slower, more robust detector");
    if (found == 0 && not_found == inputs.size()) {
        throw fail("the " + o.board + " board was found in none of the " +
                   std::to_string(inputs.size()) + " image(s). " + board_hint +
                   ". No calibration written.");
    }
    if (found == 0) {
        // Say why each view was refused: the board may well have been found, only too blurry.
        std::string why = "no usable view in the " + std::to_string(inputs.size()) +
                          " image(s): " + std::to_string(blurry) + " blurry, " +
                          std::to_string(not_found) + " without the board, " +
                          std::to_string(unreadable) + " unreadable.";
        if (blurry > 0)
            why += " Blurry: the board was found but its edges are wider than " +
                   shortest(so.detect.max_blur_px) + " px; hold it still, add light or refocus.";
        if (not_found > 0) why += " Without the board: " + board_hint + ".";
        throw fail(why + " No calibration written.");
    }
    if (static_cast<int>(found) < so.calibration.min_views) {
        throw fail("the board was found in only " + std::to_string(found) + " of " +
                   std::to_string(inputs.size()) + " image(s); at least " +
                   std::to_string(so.calibration.min_views) +
                   " views at different angles are needed (15-20 recommended). No calibration "
                   "written.");
    }

    const auto t_cal = std::chrono::steady_clock::now();
    auto res = session.calibrate();
    const double cal_s = ms_since(t_cal) / 1000;
    if (!res) throw fail(res.error().message() + ". No calibration written.");
    const CalibrationResult& r = *res;
    const CameraCalibration& cam = r.camera;

    std::cout << "\nPer image                      RMS px   lines raw/undist px   status\n";
    for (const ImageRow& row : rows) {
        std::printf("  %-28s ", row.input.name.c_str());
        if (row.view < 0) {
            std::printf("%-8s %-21s %s\n", "-", "-",
                        row.unreadable ? "unreadable" : to_string(row.status));
            continue;
        }
        const auto v = static_cast<std::size_t>(row.view);
        const auto& corners = session.views()[v];
        const double raw = max_line_deviation_px(corners, board);
        const double und = max_line_deviation_px(undistort_corners(corners, cam), board);
        char lines[32];
        std::snprintf(lines, sizeof lines, "%.2f / %.2f", raw, und);
        std::printf("%-8.3f %-21s %s\n", r.view_rms_px[v], lines,
                    r.view_used[v] ? "used" : "REJECTED (error stands out)");
    }

    const int used = r.used_views();
    std::printf("\nOverall RMS reprojection error %.3f px over %d view(s), %d corners", r.rms_px,
                used, used * board.corner_count());
    if (!r.rejected.empty()) std::printf(" (%zu view(s) rejected)", r.rejected.size());
    std::printf("\n\nParameters (± one standard deviation), %dx%d image:\n", cam.width, cam.height);
    const char* names[] = {"fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2", "k3"};
    const double values[] = {cam.fx,      cam.fy,      cam.cx,      cam.cy,     cam.dist[0],
                             cam.dist[1], cam.dist[2], cam.dist[3], cam.dist[4]};
    for (std::size_t i = 0; i < 9; ++i) {
        if (i < 4) {
            std::printf("  %-3s %10.2f ± %.2f px\n", names[i], values[i], r.std_dev[i]);
        } else {
            std::printf("  %-3s %10.5f ± %.5f\n", names[i], values[i], r.std_dev[i]);
        }
    }
    const double hfov = 2 * std::atan(cam.width / (2 * cam.fx)) * 180 / std::numbers::pi;
    const double vfov = 2 * std::atan(cam.height / (2 * cam.fy)) * 180 / std::numbers::pi;
    std::printf("  pinhole field of view %.1f° x %.1f° (the lens sees more: barrel distortion)\n",
                hfov, vfov);
    std::printf("  principal point offset from the image centre: %+.1f, %+.1f px\n",
                cam.cx - (cam.width - 1) / 2.0, cam.cy - (cam.height - 1) / 2.0);

    const CoverageMap& cov = r.coverage;
    std::printf(
        "\nCoverage: boards cover %.0f %% of the image, %d of 4 corner regions, and reach "
        "%.0f %% of the way to the image corners\n",
        100 * cov.fraction(), cov.corner_regions_covered(), 100 * cov.max_radius_fraction());
    print_coverage(cov);

    std::vector<std::string> warnings;
    if (cov.fraction() < 0.5 || cov.corner_regions_covered() < 4) {
        warnings.push_back(
            "the boards leave parts of the image uncovered; the distortion there is extrapolated. "
            "Add views with the board near the edges and in each corner.");
    }
    if (used < 10) {
        warnings.push_back("only " + std::to_string(used) +
                           " views: 15-20 at varied angles and distances give steadier numbers.");
    }
    if (r.rms_px > 1.0) {
        warnings.push_back("RMS above 1 px: check the square size, board flatness and focus.");
    }
    if (unreadable + not_found + blurry > 0) {
        warnings.push_back(std::to_string(not_found) + " image(s) without the board, " +
                           std::to_string(blurry) + " blurry, " + std::to_string(unreadable) +
                           " unreadable: skipped.");
    }
    for (const auto& w : warnings) std::cout << "warning: " << w << '\n';
    std::printf("\nTime: detection %.2f s, calibration %.2f s\n", detect_s, cal_s);

    CalibrationInfo info = r.info();
    info.camera = camera;
    CameraCalibration file_cam = cam;
    file_cam.source =
        "ardrone-gs calibrate: " + std::to_string(used) + " views of a " + o.board + " board, " +
        shortest(board.square_m * 1000) + " mm squares, from " +
        (o.inputs.size() == 1 ? o.inputs[0] : std::to_string(o.inputs.size()) + " inputs");
    if (o.out.empty()) {
        std::cout << "\nCalibration (not saved; --out FILE writes it):\n"
                  << calibration_to_json(file_cam, true, info).dump(2) << '\n';
        return;
    }
    auto saved = save_calibration_file(o.out, file_cam, info);
    if (!saved) throw fail(to_string(saved.error()));
    std::cout << "\nWrote " << o.out << '\n';
}

CommandRegistration reg(70, [](CLI::App& root) {
    auto o = std::make_shared<Opts>();
    CLI::App* c = root.add_subcommand(
        "calibrate",
        "Calibrate a camera from chessboard images (pinhole + k1 k2 p1 p2 k3) and write the "
        "calibration JSON");
    c->footer(
        "Inputs are image files, folders of images, or recorded datasets (a folder with "
        "flight.json: its video.h264 decoded, else its frames/ images; --step N takes every Nth "
        "frame).\n"
        "The output is flight.json's calibration object plus width, height, rms_px, std_dev, "
        "views and source; use it with --calibration FILE.\n"
        "Example: ardrone-gs calibrate shots/ --board 9x6 --square 0.025 --out front.json");
    c->add_option("inputs", o->inputs, "Images, image folders or dataset folders")
        ->required()
        ->type_name("IMAGE|FOLDER|DATASET")
        ->check(file_or_directory());
    c->add_option("--board", o->board, "Inner corners COLSxROWS (10x7 squares = 9x6)")
        ->required()
        ->type_name("COLSxROWS");
    c->add_option("--square", o->square_m, "Side of one square in metres")
        ->required()
        ->type_name("METRES");
    c->add_option("--out,-o", o->out,
                  "Write the calibration JSON here (nothing is written on failure)")
        ->type_name("FILE")
        ->check(output_file());
    c->add_option("--camera", o->camera, "Camera name stored in the file (front, bottom)")
        ->check(CLI::IsMember({"front", "bottom"}));
    c->add_option("--step", o->step, "Use every Nth image of a folder or dataset")->type_name("N");
    c->add_flag("--sb", o->sb,
                "Retry images without a board with OpenCV's sector-based detector (robust, ~2 s "
                "per image)");
    c->add_flag("--fix-k3", o->fix_k3, "Fit k1 k2 p1 p2 only (few views, or all near the centre)");
    set_action(*c, [o] { run(*o); });
});

}  // namespace
}  // namespace gs::app::cmd_calibrate
