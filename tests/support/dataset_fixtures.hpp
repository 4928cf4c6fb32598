#pragma once
// Shared helpers for the dataset tests: a temporary directory, small files, generated frames.

#include "drone/dataset/dataset.hpp"

#include <opencv2/core.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace gs::test {

class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::string& s) const { return path_ / s; }

private:
    std::filesystem::path path_;
};

void write_file(const std::filesystem::path& p, const std::string& text);
std::string read_file(const std::filesystem::path& p);

// A deterministic test image: frame index encoded in the pixels.
cv::Mat test_image(int index, int width, int height);

// flight.json text with the required keys (+ `extra` appended inside the object).
std::string flight_json(int width, int height, double fps, const std::string& extra = "");

// A complete dataset in `dir`: flight.json (with calibration), frames.csv with `n` rows
// (t_ms = 40*i, roll = i, pitch = -i/2, yaw = 10*i, altitude 1.5), frames/ PNGs.
void make_png_dataset(const std::filesystem::path& dir, int n, int width = 64, int height = 48);

// An assets directory with calibration/ardrone2_{front,bottom}.json (640x360).
void make_assets(const std::filesystem::path& dir);

// A fake H.264 access unit: one NAL (IDR type 5 or non-IDR type 1) whose slice starts a picture,
// with `payload` bytes that never form a start code.
std::vector<std::uint8_t> fake_access_unit(bool idr, int payload, std::uint8_t fill);

// Copies the dataset `from` to `to` keeping only frame,t_ms,roll_deg in frames.csv (the columns
// docs/dataset.md requires) and no navdata.csv: a flight whose classifier lacks velocity, altitude,
// pitch and yaw (issue 14 point 7).
void copy_attitude_only(const std::filesystem::path& from, const std::filesystem::path& to);

}  // namespace gs::test
