#pragma once
// What `replay` and `eval` write per flight: decisions.csv, the overlay MP4, the PNG plots and the
// summary / score JSON. Kept apart from the replay loop so both commands write the same files.

#include "app/mp4_writer.hpp"
#include "app/replay_run.hpp"
#include "drone/dataset/dataset.hpp"
#include "drone/dataset/scoring.hpp"
#include "vision/plot_image.hpp"
#include "vision/undistort.hpp"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace gs::app {

// A dataset directory, or a thesis-style image folder (imported in memory; `thesis_fps` is its
// frame rate when given, which a dataset directory refuses: flight.json has its own). The error
// names the path and the problem.
[[nodiscard]] Expected<dataset::Dataset, std::string> open_any_dataset(
    const std::string& path, std::optional<double> thesis_fps = std::nullopt);

std::string fixed(double v, int decimals);

class ReplayOutputs {
public:
    ReplayOutputs(std::filesystem::path dir, const CameraCalibration& calib);
    ~ReplayOutputs();
    ReplayOutputs(const ReplayOutputs&) = delete;
    ReplayOutputs& operator=(const ReplayOutputs&) = delete;

    [[nodiscard]] std::optional<std::string> open_decisions(const std::filesystem::path& file);
    [[nodiscard]] std::optional<std::string> open_video(const std::filesystem::path& file,
                                                        const dataset::DatasetInfo& info,
                                                        bool undistort);
    void enable_plots() { plots_ = true; }
    // points.csv: every tracked point of every frame as the classifier judged it (the classifier
    // must record them: ReplaySettings::record_points).
    [[nodiscard]] std::optional<std::string> open_points(const std::filesystem::path& file);

    // One frame (result null: not decoded). Errors are kept for finish().
    void frame(const FrameSample& s, const vision::FrameResult* result);
    // Closes the files; writes the plots into `plots_dir` when enabled (empty: none).
    [[nodiscard]] std::optional<std::string> finish(const std::filesystem::path& plots_dir);

private:
    void collect_series(const vision::FrameResult& r);
    std::optional<std::string> write_plots(const std::filesystem::path& dir) const;

    std::filesystem::path dir_;
    CameraCalibration calib_;
    void write_points(const FrameSample& s, const vision::FrameResult& r);

    std::FILE* decisions_ = nullptr;
    std::filesystem::path decisions_path_;
    std::FILE* points_ = nullptr;
    std::filesystem::path points_path_;
    std::unique_ptr<Mp4Writer> video_;
    bool undistort_ = false;
    vision::Undistorter undistorter_;
    cv::Mat canvas_;
    vision::Overlay mapped_;
    bool plots_ = false;
    std::string classifier_;
    // Whole-flight series (the classifier's own rings keep only the recent part).
    std::map<std::string, vision::PlotLine> series_;
    std::map<std::uint32_t, vision::PlotLine> traces_;  // trajectory x over frames, by id
    std::optional<std::string> error_;
};

nlohmann::json summary_json(const dataset::Dataset& d, const ReplaySettings& s,
                            const ReplayStats& st);
nlohmann::json score_json(const dataset::FlightScore& s);
[[nodiscard]] std::optional<std::string> write_json_file(const std::filesystem::path& file,
                                                         const nlohmann::json& j);

}  // namespace gs::app
