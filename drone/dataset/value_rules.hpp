#pragma once
// docs/dataset.md 1.1 value rules for frames.csv and navdata.csv, in one table that the readers
// check and the writer obeys: an empty cell is unknown; every other cell is a finite number (nan,
// inf and numbers that overflow a double are malformed, csv::Table::number refuses them); roll and
// pitch within ±90 degrees, each velocity within ±20 m/s, altitude within 0-20 m; yaw and the
// ground-truth columns any finite value.

#include <cmath>
#include <limits>
#include <optional>
#include <string_view>

namespace gs::dataset {

struct ValueBounds {
    double lo = 0, hi = 0;
    std::string_view unit;
};

// The physical bounds of a frames.csv / navdata.csv column, or nullopt when any finite value is
// allowed (or the column is not one the rules name).
constexpr std::optional<ValueBounds> value_bounds(std::string_view column) {
    if (column == "roll_deg" || column == "pitch_deg") return ValueBounds{-90, 90, "degrees"};
    if (column == "vx_mps" || column == "vy_mps" || column == "vz_mps")
        return ValueBounds{-20, 20, "m/s"};
    if (column == "altitude_m") return ValueBounds{0, 20, "m"};
    return std::nullopt;
}

// `v` as a writer stores it in `column`: unchanged when the rules allow it, NaN (an empty cell,
// unknown) when it is not finite or outside the column's bounds, so that every file written
// reads back.
inline double writable_value(std::string_view column, double v) {
    constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();
    if (!std::isfinite(v)) return kUnknown;
    if (auto b = value_bounds(column); b && (v < b->lo || v > b->hi)) return kUnknown;
    return v;
}

}  // namespace gs::dataset
