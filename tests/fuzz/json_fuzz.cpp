// The JSON readers: flight.json, labels.json, calibration files, the thesis folder's
// imu_meta.json. No nlohmann exception may escape (a number overflowing a double aborted replay).
// Seeds: assets/calibration, the shipped flight's flight.json and labels.json.
#include "drone/core/camera_calibration.hpp"
#include "drone/core/json_text.hpp"
#include "drone/dataset/dataset.hpp"
#include "drone/dataset/thesis.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto in = gs::fuzz::split(data, size, 5);
    const std::string text = in.text();
    switch (in.choice) {
        case 0: {
            std::vector<std::string> warnings;
            (void)gs::dataset::parse_flight_json(text, gs::dataset::DatasetLimits{}, &warnings);
            break;
        }
        case 1:
            (void)gs::dataset::parse_labels_json(text);
            break;
        case 2:
            if (auto j = gs::parse_json_text(text, "calibration.json"))
                (void)gs::calibration_from_json(*j);
            break;
        case 3:
            (void)gs::parse_calibration(text, "calibration.json");
            break;
        default:
            (void)gs::dataset::read_thesis_texts("0 0 0 0 0\n", text.empty() ? "{}" : text);
            break;
    }
    return 0;
}
