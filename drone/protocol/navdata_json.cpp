#include "drone/protocol/navdata_json.hpp"

#include "drone/protocol/navdata_layout.hpp"

namespace gs::protocol::navdata {

namespace {

template <class T>
nlohmann::json field_json(const T& v) {
    if constexpr (std::is_arithmetic_v<T>) {
        return v;
    } else if constexpr (std::is_same_v<T, GpsChannel>) {
        return nlohmann::json{{"sat", v.sat}, {"cn0", v.cn0}};
    } else {
        nlohmann::json a = nlohmann::json::array();
        for (const auto& e : v) a.push_back(field_json(e));
        return a;
    }
}

template <class T>
nlohmann::json option_json(const T& opt) {
    nlohmann::json o = nlohmann::json::object();
    layout::Spec<T>::fields(
        opt, [&](std::size_t, std::string_view name, std::string_view, const auto& field) {
            o[std::string(name)] = field_json(field);
        });
    return o;
}

nlohmann::json optional_name(std::optional<std::string_view> n) {
    if (n) return std::string(*n);
    return nullptr;
}

}  // namespace

nlohmann::json drone_state_to_json(DroneState s) {
    nlohmann::json j = nlohmann::json::object();
    j["raw"] = s.raw;
    for (unsigned i = 0; i < 32; ++i) j[std::string(kDroneStateBits[i].name)] = s.bit(i);
    return j;
}

nlohmann::json to_json(const Navdata& nd) {
    nlohmann::json j = nlohmann::json::object();
    j["header"] = nd.header.magic;
    j["drone_state"] = nd.header.drone_state.raw;
    j["drone_state_bits"] = drone_state_to_json(nd.header.drone_state);
    j["sequence"] = nd.header.sequence;
    j["vision_defined"] = nd.header.vision_defined;

    nlohmann::json opts = nlohmann::json::array();
    for (const OptionEntry& e : nd.options) {
        opts.push_back({{"offset", e.offset},
                        {"tag", e.tag},
                        {"size", e.size},
                        {"name", optional_name(option_name(e.tag, e.size))}});
    }
    j["options"] = std::move(opts);
    j["options_not_listed"] = nd.options.overflow();
    nlohmann::json skipped = nlohmann::json::array();
    for (const SkippedOption& s : nd.skipped) {
        skipped.push_back({{"offset", s.option.offset},
                           {"tag", s.option.tag},
                           {"size", s.option.size},
                           {"reason", std::string(to_string(s.reason))}});
    }
    j["skipped"] = std::move(skipped);
    j["skipped_not_listed"] = nd.skipped.overflow();
    j["checksum"] = nd.checksum;
    j["checksum_offset"] = nd.checksum_offset;
    j["trailing_bytes"] = nd.trailing_bytes;

    layout::for_each_option_type([&]<class T>(std::type_identity<T>) {
        using S = layout::Spec<T>;
        if (const auto& opt = nd.*S::member) j[std::string(S::name)] = option_json(*opt);
    });
    if (nd.demo) {
        const CtrlState c = nd.demo->ctrl_state;
        auto& d = j["demo"];
        d["ctrl_state_major"] = c.major();
        d["ctrl_state_major_name"] = optional_name(ctrl_major_name(c.major()));
        d["ctrl_state_minor"] = c.minor();
        d["ctrl_state_minor_name"] = optional_name(ctrl_minor_name(c.major(), c.minor()));
    }
    if (nd.time) {
        auto& t = j["time"];
        t["time_seconds"] = nd.time->time.seconds();
        t["time_microseconds"] = nd.time->time.microseconds();
        t["time_s"] = nd.time->time.total_s();
    }
    return j;
}

}  // namespace gs::protocol::navdata
