#pragma once
// JSON views of PaVE headers and framer events, with docs/protocol.md §4.1 field names
// (used by `inspect pave`, and by anything that records or reports video frames).

#include "drone/protocol/pave.hpp"

#include <nlohmann/json.hpp>

namespace gs::protocol {

// Every header field by its SDK name; video_codec/frame_type as numbers plus *_name strings;
// reserved and extension bytes as arrays (extension only when header_size >= 68).
[[nodiscard]] nlohmann::json to_json(const PaveHeader& h);
// {"offset", "bytes_skipped", "resume_offset", "reason"}
[[nodiscard]] nlohmann::json to_json(const PaveResync& r);
// {"bytes_in", "frames", "payload_bytes", "resyncs", "bytes_skipped", "oversize_rejections"}
[[nodiscard]] nlohmann::json to_json(const PaveFramerStats& s);

}  // namespace gs::protocol
