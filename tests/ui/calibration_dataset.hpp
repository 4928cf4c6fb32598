#pragma once
// A replay dataset of the 11 real AR.Drone 2 chessboard frames (rjw57, 9x6 inner corners, 50 mm
// squares, 640x360) built in a temporary folder (flight.json + frames.csv + frames/NNNNNN.png,
// docs/dataset.md), for the window's calibration mode. The fixtures are read from GS_FIXTURES_DIR
// and never copied into the repository.

#include "drone/core/camera_calibration.hpp"

#include <filesystem>
#include <string>

namespace gs::ui::test {

inline constexpr int kChessboardFrames = 11;

struct ChessboardDatasetOptions {
    // The dataset's own calibration (flight.json): deliberately off by default (fx 500, no
    // distortion), so a calibration applied by the mode is told apart from the dataset's.
    CameraCalibration calibration = [] {
        CameraCalibration c;
        c.fx = c.fy = 500.0;
        c.cx = 320.0;
        c.cy = 180.0;
        c.width = 640;
        c.height = 360;
        return c;
    }();
    // Append a frame without a board (grey noise) after the chessboard frames.
    bool add_empty_frame = true;
};

// Writes the dataset into `dir` (created, emptied first). Returns "" or what went wrong.
std::string write_chessboard_dataset(const std::filesystem::path& dir,
                                     const ChessboardDatasetOptions& opt = {});

// Frame file of the fixture folder (frame0000.jpg ...).
std::filesystem::path chessboard_fixture(int i);

}  // namespace gs::ui::test
