#pragma once
// Typed errors of camera calibration (finding boards, solving for the intrinsics, saving the
// result). Calibration files themselves are read and written by drone/core/camera_calibration.hpp.

#include "drone/core/expected.hpp"

#include <string>
#include <utility>

namespace gs::vision {

enum class CalibrationErrorKind {
    NoImages,           // nothing to calibrate from
    ImageUnreadable,    // a file is not an image OpenCV can decode
    ImageSizeMismatch,  // images of different sizes in one calibration
    BoardNotFound,      // the board was found in no image (or too few)
    TooFewViews,        // fewer usable views than needed
    BadBoardSpec,       // board size or square size invalid
    CalibrationFailed,  // the optimiser returned nonsense (non-finite or non-positive focal length)
    FileWrite,          // the calibration file cannot be written
};

[[nodiscard]] const char* to_string(CalibrationErrorKind k);

struct CalibrationError {
    CalibrationErrorKind kind;
    std::string detail;  // what, where: shown to the user as is

    // "<kind>: <detail>" for messages.
    [[nodiscard]] std::string message() const;
};

// The error as an Expected's unexpected value: `return calibration_error(kind, "...");`.
inline Unexpected<CalibrationError> calibration_error(CalibrationErrorKind k, std::string detail) {
    return Unexpected(CalibrationError{k, std::move(detail)});
}

}  // namespace gs::vision
