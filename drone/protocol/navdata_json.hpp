#pragma once
// Navdata -> JSON with docs/protocol.md §3 field names (the SDK identifiers, no unit suffixes): one
// object per present option, plus the header, the drone_state bits by name, the option list,
// the skipped options and the checksum. For `inspect navdata --json` and dataset metadata.

#include "drone/protocol/navdata.hpp"

#include <nlohmann/json.hpp>

namespace gs::protocol::navdata {

// {"header", "drone_state", "drone_state_bits": {"FLY": false, ...}, "sequence", "vision_defined",
//  "options": [{"offset","tag","size","name"}], "skipped": [...], "checksum", "checksum_offset",
//  "trailing_bytes", "<option name>": {field: value, ...}, ...}. demo adds ctrl_state_major/minor
// (+ _name, null when unnamed); time adds time_seconds, time_microseconds, time_s.
[[nodiscard]] nlohmann::json to_json(const Navdata& nd);

// {"raw": n, "FLY": bool, ... all 32 bits}.
[[nodiscard]] nlohmann::json drone_state_to_json(DroneState s);

}  // namespace gs::protocol::navdata
