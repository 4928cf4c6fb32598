#pragma once
// Typed errors of camera calibration and of calibration files, and a small value-or-error result.
// vision/ may not include drone/expected.hpp, so this is the vision-side equivalent (same shape).

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace gs::vision {

enum class CalibrationErrorKind {
    NoImages,           // nothing to calibrate from
    ImageUnreadable,    // a file is not an image OpenCV can decode
    ImageSizeMismatch,  // images of different sizes in one calibration
    BoardNotFound,      // the board was found in no image (or too few)
    TooFewViews,        // fewer usable views than needed
    BadBoardSpec,       // board size or square size invalid
    CalibrationFailed,  // the optimiser returned nonsense (non-finite or non-positive focal length)
    FileRead,           // a calibration file cannot be opened
    FileWrite,          // a calibration file cannot be written
    BadJson,            // a calibration file is not valid JSON or misses required fields
    BadValue,           // a calibration file holds out-of-range values
};

[[nodiscard]] const char* to_string(CalibrationErrorKind k);

struct CalibrationError {
    CalibrationErrorKind kind;
    std::string detail;  // what, where: shown to the user as is

    // "<kind>: <detail>" for messages.
    [[nodiscard]] std::string message() const;
};

inline CalibrationError calibration_error(CalibrationErrorKind k, std::string detail) {
    return {k, std::move(detail)};
}

template <class T>
class [[nodiscard]] CalibrationExpected {
public:
    CalibrationExpected(T value) : v_(std::in_place_index<0>, std::move(value)) {}         // NOLINT
    CalibrationExpected(CalibrationError e) : v_(std::in_place_index<1>, std::move(e)) {}  // NOLINT

    bool has_value() const noexcept { return v_.index() == 0; }
    explicit operator bool() const noexcept { return has_value(); }

    T& value() & {
        assert(has_value());
        return std::get<0>(v_);
    }
    const T& value() const& {
        assert(has_value());
        return std::get<0>(v_);
    }
    T&& value() && {
        assert(has_value());
        return std::get<0>(std::move(v_));
    }
    const CalibrationError& error() const {
        assert(!has_value());
        return std::get<1>(v_);
    }

    T& operator*() & { return value(); }
    const T& operator*() const& { return value(); }
    T* operator->() { return &value(); }
    const T* operator->() const { return &value(); }

private:
    std::variant<T, CalibrationError> v_;
};

// For operations with no value (save).
struct Done {};

}  // namespace gs::vision
