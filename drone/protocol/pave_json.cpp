#include "drone/protocol/pave_json.hpp"

#include <string>

namespace gs::protocol {

nlohmann::json to_json(const PaveHeader& h) {
    nlohmann::json j;
    j["signature"] = std::string(h.signature.begin(), h.signature.end());
    j["version"] = h.version;
    j["video_codec"] = static_cast<unsigned>(h.video_codec);
    j["video_codec_name"] = to_string(h.video_codec);
    j["header_size"] = h.header_size;
    j["payload_size"] = h.payload_size;
    j["encoded_stream_width"] = h.encoded_stream_width;
    j["encoded_stream_height"] = h.encoded_stream_height;
    j["display_width"] = h.display_width;
    j["display_height"] = h.display_height;
    j["frame_number"] = h.frame_number;
    j["timestamp"] = h.timestamp;
    j["total_chuncks"] = h.total_chuncks;
    j["chunck_index"] = h.chunck_index;
    j["frame_type"] = static_cast<unsigned>(h.frame_type);
    j["frame_type_name"] = to_string(h.frame_type);
    j["control"] = h.control;
    j["stream_byte_position_lw"] = h.stream_byte_position_lw;
    j["stream_byte_position_uw"] = h.stream_byte_position_uw;
    j["stream_id"] = h.stream_id;
    j["total_slices"] = h.total_slices;
    j["slice_index"] = h.slice_index;
    j["header1_size"] = h.header1_size;
    j["header2_size"] = h.header2_size;
    j["reserved2"] = h.reserved2;
    j["advertised_size"] = h.advertised_size;
    j["reserved3"] = h.reserved3;
    if (h.header_size >= kPaveBaseHeaderSize + 4) j["extension"] = h.extension;
    return j;
}

nlohmann::json to_json(const PaveResync& r) {
    return {{"offset", r.stream_offset},
            {"bytes_skipped", r.bytes_skipped},
            {"resume_offset", r.stream_offset + r.bytes_skipped},
            {"reason", to_string(r.reason)}};
}

nlohmann::json to_json(const PaveFramerStats& s) {
    return {{"bytes_in", s.bytes_in},           {"frames", s.frames},
            {"payload_bytes", s.payload_bytes}, {"resyncs", s.resyncs},
            {"bytes_skipped", s.bytes_skipped}, {"oversize_rejections", s.oversize_rejections}};
}

}  // namespace gs::protocol
