#ifdef GS_HAVE_GUI

// Telemetry view: the navdata as fields (live) or the dataset's navdata stream (replay), the drone
// state bits and whether an emergency the drone reports was commanded from here.

#include "app/gui_adapter.hpp"
#include "app/gui_views.hpp"
#include "drone/protocol/navdata_layout.hpp"

#include <cmath>
#include <cstdio>
#include <type_traits>

namespace gs::app {

namespace {

// One navdata field as text: numbers with %g, arrays as [a, b, ...].
template <class T>
void format_field(std::string& out, const T& v) {
    if constexpr (std::is_same_v<T, bool>) {
        out += v ? "1" : "0";
    } else if constexpr (std::is_floating_point_v<T>) {
        char b[32];
        std::snprintf(b, sizeof b, "%.6g", static_cast<double>(v));
        out += b;
    } else if constexpr (std::is_arithmetic_v<T>) {
        out += std::to_string(+v);
    } else if constexpr (std::is_same_v<T, protocol::navdata::GpsChannel>) {
        out += "{sat " + std::to_string(+v.sat) + ", cn0 " + std::to_string(+v.cn0) + "}";
    } else {
        out += '[';
        bool first = true;
        for (const auto& e : v) {
            if (!first) out += ", ";
            first = false;
            format_field(out, e);
        }
        out += ']';
    }
}

}  // namespace

// Every field of every option present, grouped by option, in wire order, names with units.
void navdata_fields(const protocol::navdata::Navdata& nd, std::vector<ui::TelemetryField>& out) {
    out.clear();
    protocol::navdata::layout::for_each_option_type([&]<class T>(std::type_identity<T>) {
        using S = protocol::navdata::layout::Spec<T>;
        const auto& opt = nd.*S::member;
        if (!opt) return;
        S::fields(*opt, [&](std::size_t, std::string_view name, std::string_view unit,
                            const auto& field) {
            ui::TelemetryField f;
            f.group = std::string(S::name);
            f.name = std::string(name);
            if (!unit.empty()) f.name += " [" + std::string(unit) + "]";
            format_field(f.value, field);
            out.push_back(std::move(f));
        });
    });
}

void GuiAdapter::fill_telemetry(ui::GuiSnapshot& s) {
    ui::Telemetry& t = s.telemetry;
    if (source_.link) {
        if (source_.link->navdata().read_if_newer(nav_gen_, nav_)) {
            nav_valid_ = true;
            nav_dirty_ = true;
        }
        t.valid = nav_valid_;
        t.battery_low_pct = source_.link->config_used().min_takeoff_battery_pct;
        if (!nav_valid_) {
            t.fields.clear();
            t.state.reset();
            t.ctrl_state.clear();
            return;
        }
        t.nav = nav_.state;
        if (nav_dirty_) {
            navdata_fields(nav_.data, t.fields);
            nav_dirty_ = false;
        }
        t.age_ms = age_ms(clock_.now_ns(), nav_.recv_ns);
        t.stale = known(t.age_ms) && t.age_ms > ui::kStaleAfterMs;
    } else if (source_.kind == SessionSource::Replay) {
        if (session_.replay_nav().read_if_newer(rnav_gen_, replay_nav_)) replay_nav_valid_ = true;
        t.valid = replay_nav_valid_;
        t.nav = replay_nav_;
        t.fields.clear();
        if (!replay_nav_valid_) return;
        auto num = [&](const char* name, double v, const char* unit) {
            char b[48];
            std::snprintf(b, sizeof b, "%.3f", v);
            t.fields.push_back({"dataset", std::string(name) + " [" + unit + "]",
                                std::isfinite(v) ? b : "unknown"});
        };
        num("roll", replay_nav_.roll_deg, "deg");
        num("pitch", replay_nav_.pitch_deg, "deg");
        num("yaw", replay_nav_.yaw_deg, "deg");
        num("vx", replay_nav_.vx_mps, "m/s");
        num("vy", replay_nav_.vy_mps, "m/s");
        num("vz", replay_nav_.vz_mps, "m/s");
        num("altitude", replay_nav_.altitude_m, "m");
        num("battery", replay_nav_.battery_pct, "%");
        t.age_ms = kUnknown;  // a recording is not live: nothing goes stale
        t.stale = false;
    } else {
        t = ui::Telemetry{};
        return;
    }
    if (t.nav.drone_state)
        t.state = ui::DroneStateBits::from_raw(*t.nav.drone_state);
    else
        t.state.reset();
    t.ctrl_state = t.nav.ctrl_state ? ui::ctrl_state_name(*t.nav.ctrl_state) : std::string{};
    // Was the emergency the drone reports commanded from here? Yes when its bit rose within a
    // few seconds of our Emergency; a cut-out nobody asked for is a fault (Why not flying).
    const bool bit = source_.link && t.state && t.state->emergency;
    if (bit && !prev_emergency_bit_)
        emergency_commanded_ =
            emergency_sent_ns_ > 0 && clock_.now_ns() - emergency_sent_ns_ < ms_to_ns(3000);
    if (!bit) emergency_commanded_ = false;
    prev_emergency_bit_ = bit;
    t.emergency_commanded = emergency_commanded_;
}

}  // namespace gs::app

#endif  // GS_HAVE_GUI
