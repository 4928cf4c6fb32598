#include "ui/windows.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <string_view>

namespace gs::ui {

namespace {

constexpr std::uint32_t kHud = IM_COL32(235, 242, 248, 255);
constexpr std::uint32_t kShadow = IM_COL32(0, 0, 0, 200);
constexpr std::uint32_t kPanel = IM_COL32(0, 0, 0, 150);
constexpr std::uint32_t kSymbol = IM_COL32(255, 200, 40, 255);

void text(ImDrawList* dl, ImVec2 p, std::uint32_t col, const char* s, float size = 0) {
    ImFont* f = ImGui::GetFont();
    if (size <= 0) size = ImGui::GetFontSize();
    dl->AddText(f, size, {p.x + 1, p.y + 1}, kShadow, s);
    dl->AddText(f, size, p, col, s);
}
ImVec2 text_size(const char* s, float size = 0) {
    if (size <= 0) size = ImGui::GetFontSize();
    return ImGui::GetFont()->CalcTextSizeA(size, FLT_MAX, 0, s);
}
void text(ImDrawList* dl, ImVec2 p, std::uint32_t col, std::string_view s, float size) {
    ImFont* f = ImGui::GetFont();
    dl->AddText(f, size, {p.x + 1, p.y + 1}, kShadow, s.data(), s.data() + s.size());
    dl->AddText(f, size, p, col, s.data(), s.data() + s.size());
}
ImVec2 text_size(std::string_view s, float size) {
    return ImGui::GetFont()->CalcTextSizeA(size, FLT_MAX, 0, s.data(), s.data() + s.size());
}

// One line of a wrapped banner: a view into the message, and its size (measured once).
struct BannerLine {
    std::string_view text;
    float w = 0, h = 0;
};
constexpr std::size_t kMaxBannerLines = 8;

// Greedy word wrap at spaces: as many words on each line as fit in max_w (a word longer than
// that gets a line of its own); the last line takes whatever is left. No allocation. Returns the
// number of lines written to `out`.
std::size_t wrap_at_spaces(std::string_view msg, float size, float max_w,
                           std::array<BannerLine, kMaxBannerLines>& out) {
    std::size_t n = 0;
    std::size_t at = msg.find_first_not_of(' ');
    while (at != std::string_view::npos && n < out.size()) {
        std::size_t end = msg.find(' ', at);  // the first word always fits
        if (end == std::string_view::npos) end = msg.size();
        ImVec2 ts = text_size(msg.substr(at, end - at), size);
        while (end < msg.size()) {
            const std::size_t next = msg.find_first_not_of(' ', end);
            if (next == std::string_view::npos) break;
            std::size_t word_end = msg.find(' ', next);
            if (word_end == std::string_view::npos) word_end = msg.size();
            const ImVec2 wider = text_size(msg.substr(at, word_end - at), size);
            if (wider.x > max_w && n + 1 < out.size()) break;
            end = word_end;
            ts = wider;
        }
        out[n++] = {msg.substr(at, end - at), ts.x, ts.y};
        at = end < msg.size() ? msg.find_first_not_of(' ', end) : std::string_view::npos;
    }
    return n;
}
void line(ImDrawList* dl, ImVec2 a, ImVec2 b, std::uint32_t col, float th) {
    dl->AddLine({a.x + 1, a.y + 1}, {b.x + 1, b.y + 1}, kShadow, th);
    dl->AddLine(a, b, col, th);
}

// Boxed read-out: "LABEL value unit", left- or right-anchored. Returns where it was drawn.
Rect readout(ImDrawList* dl, ImVec2 anchor, bool right, const char* label, const char* value,
             std::uint32_t col) {
    const float fs = ImGui::GetFontSize();
    const ImVec2 ls = text_size(label, fs * 0.85f), vs = text_size(value, fs * 1.25f);
    const float w = std::max(ls.x, vs.x) + 14, h = ls.y + vs.y + 6;
    const ImVec2 b0{right ? anchor.x - w : anchor.x, anchor.y};
    const ImVec2 b1{b0.x + w, b0.y + h};
    dl->AddRectFilled(b0, b1, kPanel, 3.0f);
    dl->AddRect(b0, b1, IM_COL32(255, 255, 255, 60), 3.0f);
    text(dl, {b0.x + 7, b0.y + 2}, colors::kDim, label, fs * 0.85f);
    text(dl, {b0.x + 7, b0.y + 3 + ls.y}, col, value, fs * 1.25f);
    return {b0.x, b0.y, b1.x, b1.y};
}

bool overlaps(const Rect& a, const Rect& b) {
    return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
}

const char* compass(double deg) {
    static const char* names[] = {"N", "NE", "E", "SE", "S", "SW", "W", "NW"};
    const int i = static_cast<int>(std::lround(deg / 45.0)) & 7;
    return names[i];
}

}  // namespace

void Hud::draw(ImDrawList* dl, ImVec2 p0, ImVec2 p1, const GuiSnapshot& s, ViewState& v) {
    const float W = p1.x - p0.x, H = p1.y - p0.y;
    const float fs = ImGui::GetFontSize();
    const NavState& n = s.telemetry.nav;
    const bool nav = s.telemetry.valid;
    // Stale navdata (live, older than kStaleAfterMs): the attitude, heading, speeds and altitude
    // are the last received, drawn dimmed under a NAVDATA STALE label, never as the state now.
    const bool stale = nav && s.telemetry.stale;
    const std::uint32_t value_col = stale ? colors::kDim : kHud;
    const std::uint32_t value_soft = stale ? colors::kDim : IM_COL32(235, 242, 248, 170);
    const ImVec2 c{p0.x + W * 0.5f, p0.y + H * 0.5f};
    char buf[128];
    dl->PushClipRect(p0, p1, true);

    // ---- Artificial horizon (roll, pitch) in a central box --------------------------------
    const float hr = std::min(W, H) * 0.30f;  // half-size of the horizon box
    if (nav && known(n.roll_deg) && known(n.pitch_deg)) {
        const float r = static_cast<float>(n.roll_deg * std::numbers::pi / 180.0);
        const float ppd = hr / 25.0f;  // pixels per degree of pitch: +-25 deg fills the box
        const ImVec2 dir{std::cos(r),
                         -std::sin(r)};  // along the horizon (right wing up when rolled right)
        const ImVec2 down{std::sin(r), std::cos(r)};  // perpendicular, screen-down when level
        dl->PushClipRect({c.x - hr * 1.3f, c.y - hr}, {c.x + hr * 1.3f, c.y + hr}, true);
        for (int k = -30; k <= 30; k += 5) {
            const float off = static_cast<float>(n.pitch_deg - k) * ppd;
            const ImVec2 m{c.x + down.x * off, c.y + down.y * off};
            const float half = k == 0 ? hr * 1.3f : (k % 10 == 0 ? hr * 0.32f : hr * 0.16f);
            const ImVec2 a{m.x - dir.x * half, m.y - dir.y * half},
                b{m.x + dir.x * half, m.y + dir.y * half};
            if (k == 0) {
                line(dl, a, b, value_col, 2.0f);
            } else {
                line(dl, a, b, value_soft, 1.0f);
                if (k % 10 == 0) {
                    std::snprintf(buf, sizeof buf, "%d", k);
                    text(dl, {b.x + 4, b.y - fs * 0.5f}, value_soft, buf, fs * 0.8f);
                }
            }
        }
        dl->PopClipRect();
        std::snprintf(buf, sizeof buf, "R %+5.1f\xc2\xb0  P %+5.1f\xc2\xb0", n.roll_deg,
                      n.pitch_deg);
        const ImVec2 ts = text_size(buf);
        text(dl, {c.x - ts.x * 0.5f, c.y + hr + 4}, value_col, buf);
    } else {
        const char* msg = "NO ATTITUDE";
        const ImVec2 ts = text_size(msg);
        text(dl, {c.x - ts.x * 0.5f, c.y + hr * 0.4f}, colors::kWarn, msg);
    }
    if (stale) {
        std::snprintf(buf, sizeof buf, "NAVDATA STALE %.1f s", s.telemetry.age_ms / 1000.0);
        const ImVec2 ts = text_size(buf);
        const ImVec2 b0{c.x - ts.x * 0.5f - 6, c.y - hr * 0.55f - 2};
        dl->AddRectFilled(b0, {b0.x + ts.x + 12, b0.y + ts.y + 4}, IM_COL32(0, 0, 0, 200), 3.0f);
        text(dl, {b0.x + 6, b0.y + 2}, colors::kWarn, buf);
        v.layout.hud_stale_text = buf;
    }
    // Fixed aircraft symbol.
    const float sw = hr * 0.22f;
    line(dl, {c.x - sw * 2.2f, c.y}, {c.x - sw, c.y}, kSymbol, 3.0f);
    line(dl, {c.x - sw, c.y}, {c.x - sw * 0.5f, c.y + sw * 0.5f}, kSymbol, 3.0f);
    line(dl, {c.x - sw * 0.5f, c.y + sw * 0.5f}, {c.x, c.y}, kSymbol, 3.0f);
    line(dl, {c.x, c.y}, {c.x + sw * 0.5f, c.y + sw * 0.5f}, kSymbol, 3.0f);
    line(dl, {c.x + sw * 0.5f, c.y + sw * 0.5f}, {c.x + sw, c.y}, kSymbol, 3.0f);
    line(dl, {c.x + sw, c.y}, {c.x + sw * 2.2f, c.y}, kSymbol, 3.0f);

    // ---- Heading tape (top centre, below the region bar) -----------------------------------
    const float tape_y = p0.y + std::max(16.0f, H * 0.04f) + 6.0f;
    const float tape_w = std::min(W * 0.46f, 460.0f), tape_h = fs * 2.4f;
    const ImVec2 t0{c.x - tape_w * 0.5f, tape_y}, t1{c.x + tape_w * 0.5f, tape_y + tape_h};
    dl->AddRectFilled(t0, t1, kPanel, 3.0f);
    if (nav && known(n.yaw_deg)) {
        const double hdg = std::fmod(std::fmod(n.yaw_deg, 360.0) + 360.0, 360.0);
        const float ppd = tape_w / 70.0f;  // +-35 deg visible
        dl->PushClipRect(t0, t1, true);
        const int first = static_cast<int>(std::floor((hdg - 40) / 5.0)) * 5;
        for (int d = first; d <= hdg + 40; d += 5) {
            const float x = c.x + static_cast<float>(d - hdg) * ppd;
            const bool major = (d % 10) == 0;
            line(dl, {x, t1.y - (major ? fs * 0.7f : fs * 0.4f)}, {x, t1.y}, value_col, 1.0f);
            if (d % 30 == 0) {
                const int dd = ((d % 360) + 360) % 360;
                if (dd % 90 == 0)
                    std::snprintf(buf, sizeof buf, "%s", compass(dd));
                else
                    std::snprintf(buf, sizeof buf, "%d", dd);
                const ImVec2 ts = text_size(buf, fs * 0.85f);
                text(dl, {x - ts.x * 0.5f, t0.y + 2}, value_col, buf, fs * 0.85f);
            }
        }
        dl->PopClipRect();
        std::snprintf(buf, sizeof buf, "%03.0f\xc2\xb0 %s", hdg, compass(hdg));
        const ImVec2 ts = text_size(buf);
        const ImVec2 b0{c.x - ts.x * 0.5f - 5, t1.y + 2},
            b1{c.x + ts.x * 0.5f + 5, t1.y + ts.y + 5};
        dl->AddRectFilled(b0, b1, IM_COL32(0, 0, 0, 210), 2.0f);
        dl->AddRect(b0, b1, value_col, 2.0f);
        text(dl, {b0.x + 5, b0.y + 1}, value_col, buf);
        dl->AddTriangleFilled({c.x - 5, t1.y}, {c.x + 5, t1.y}, {c.x, t1.y - 6}, kSymbol);
    } else {
        const ImVec2 ts = text_size("HDG ---");
        text(dl, {c.x - ts.x * 0.5f, t0.y + (tape_h - ts.y) * 0.5f}, colors::kDim, "HDG ---");
    }

    // ---- Speeds (left) and altitude (right) -------------------------------------------------
    const float side_y = c.y - fs * 2.2f;
    const double gs =
        (known(n.vx_mps) && known(n.vy_mps)) ? std::hypot(n.vx_mps, n.vy_mps) : kUnknown;
    if (nav && known(gs))
        std::snprintf(buf, sizeof buf, "%.2f m/s", gs);
    else
        std::snprintf(buf, sizeof buf, "--- m/s");
    std::array<Rect, 3> readouts{};  // kept clear of the assist banner below
    readouts[0] = readout(dl, {p0.x + W * 0.06f, side_y}, false, "GROUND SPEED", buf, value_col);
    if (nav && known(n.vz_mps))
        std::snprintf(buf, sizeof buf, "%+.2f m/s", n.vz_mps);
    else
        std::snprintf(buf, sizeof buf, "--- m/s");
    readouts[1] = readout(dl, {p0.x + W * 0.06f, side_y + fs * 3.4f}, false, "VERTICAL SPEED", buf,
                          value_col);
    if (nav && known(n.altitude_m))
        std::snprintf(buf, sizeof buf, "%.2f m", n.altitude_m);
    else
        std::snprintf(buf, sizeof buf, "--- m");
    readouts[2] = readout(dl, {p1.x - W * 0.06f, side_y}, true, "ALTITUDE", buf, value_col);
    v.layout.labels.push_back({"hud.ground_speed", readouts[0]});
    v.layout.labels.push_back({"hud.vertical_speed", readouts[1]});
    v.layout.labels.push_back({"hud.altitude", readouts[2]});

    // ---- Bottom strip: battery, control state, link, video --------------------------------
    const float strip_h = fs * 1.9f;
    const ImVec2 s0{p0.x, p1.y - strip_h}, s1{p1.x, p1.y};
    dl->AddRectFilled(s0, s1, IM_COL32(0, 0, 0, 175));
    float x = s0.x + 10;
    const float cy = s0.y + strip_h * 0.5f;

    // Battery gauge: outline, terminal nub, fill proportional to percent.
    const double bat = nav ? n.battery_pct : kUnknown;
    const bool bat_known = known(bat);
    const bool bat_low = (bat_known && bat < s.telemetry.battery_low_pct) ||
                         (s.telemetry.state && s.telemetry.state->battery_low);
    const float gw = fs * 4.2f, gh = fs * 1.05f;
    const ImVec2 g0{x, cy - gh * 0.5f}, g1{x + gw, cy + gh * 0.5f};
    const float frac = bat_known ? static_cast<float>(std::clamp(bat, 0.0, 100.0) / 100.0) : 0.0f;
    const std::uint32_t bcol = !bat_known ? colors::kDim
                               : bat_low  ? colors::kBad
                               : bat < 40 ? colors::kWarn
                                          : colors::kGood;
    const ImVec2 f0{g0.x + 2, g0.y + 2};
    const ImVec2 f1{g0.x + 2 + (gw - 4) * frac, g1.y - 2};
    dl->AddRectFilled(g0, g1, IM_COL32(30, 30, 30, 230), 2.0f);
    if (frac > 0) dl->AddRectFilled(f0, f1, bcol, 1.0f);
    dl->AddRect(g0, g1, kHud, 2.0f, 0, 1.5f);
    dl->AddRectFilled({g1.x, cy - gh * 0.22f}, {g1.x + 3, cy + gh * 0.22f}, kHud);
    if (bat_known)
        std::snprintf(buf, sizeof buf, "%.0f%%", bat);
    else
        std::snprintf(buf, sizeof buf, "---%%");
    text(dl, {g1.x + 8, cy - fs * 0.5f}, bat_low ? colors::kBad : kHud, buf);
    v.layout.battery_outline = {g0.x, g0.y, g1.x, g1.y};
    v.layout.battery_fill = {f0.x, f0.y, frac > 0 ? f1.x : f0.x, f1.y};
    v.layout.battery_color = bcol;
    v.layout.battery_text = buf;
    v.layout.battery_warning = bat_low;
    x = g1.x + 8 + text_size("100%").x + 18;

    // A field is drawn whole or not at all (the status bar above has them all): never cut at the
    // picture's edge.
    float strip_end = x;
    auto fits = [&](const char* label, const std::string& value) {
        return x + text_size(label).x + 5 + text_size(value.c_str()).x <= s1.x - 8;
    };
    auto field = [&](const char* label, const std::string& value, std::uint32_t col) {
        if (!fits(label, value)) return;
        text(dl, {x, cy - fs * 0.5f}, colors::kDim, label);
        x += text_size(label).x + 5;
        text(dl, {x, cy - fs * 0.5f}, col, value.c_str());
        strip_end = x + text_size(value.c_str()).x;
        x = strip_end + 18;
    };
    field("STATE", s.telemetry.ctrl_state.empty() ? "---" : s.telemetry.ctrl_state,
          s.telemetry.state && s.telemetry.state->flying ? colors::kInfo : kHud);
    {
        const LinkState ls = s.connection.state;
        std::uint32_t col = ls == LinkState::Connected ? colors::kGood
                            : ls == LinkState::Replay  ? colors::kInfo
                            : ls == LinkState::Lost    ? colors::kBad
                                                       : colors::kWarn;
        std::string val = to_string(ls);
        const double age = s.link.navdata.age_ms;
        if (known(age) && ls != LinkState::Disconnected) {
            std::snprintf(buf, sizeof buf, " %.0f ms", age);
            val += buf;
            if (age > 500 && col == colors::kGood) col = colors::kWarn;
        }
        field("LINK", val, col);
    }
    {
        std::string val = "---";
        if (!s.video.bgr.empty()) {
            std::snprintf(buf, sizeof buf, "%.1f fps", s.video.fps);
            val = known(s.video.fps) ? buf : "-- fps";
            if (known(s.video.latency_ms)) {
                std::snprintf(buf, sizeof buf, "  %.0f ms", s.video.latency_ms);
                if (fits("VIDEO", val + buf)) val += buf;  // the latency goes first when narrow
            }
        }
        field("VIDEO", val, s.video.bgr.empty() ? colors::kWarn : kHud);
    }
    if (s.recording.active) {
        const std::string rec = format_duration(s.recording.duration_s);
        x += 16;
        if (fits("REC", rec)) {
            dl->AddCircleFilled({x - 10, cy}, 6.0f, colors::kBad);
            field("REC", rec, colors::kBad);
        }
    }
    v.layout.labels.push_back({"hud.strip", {s0.x, s0.y, s1.x, s1.y}});
    v.layout.labels.push_back({"hud.strip_end", {strip_end, s0.y, strip_end, s1.y}});

    // ---- Warnings, centre-top, largest type -------------------------------------------------
    struct Warning {
        const char* text;
        std::uint32_t col;
    };
    std::array<Warning, 3> warnings{};  // link, emergency, battery: at most one of each
    std::size_t n_warn = 0;
    const LinkState ls = s.connection.state;
    if (ls == LinkState::Lost)
        warnings[n_warn++] = {"LINK LOST", colors::kBad};
    else if (ls == LinkState::Disconnected)
        warnings[n_warn++] = {"NO LINK", colors::kWarn};
    else if (ls == LinkState::Connecting)
        warnings[n_warn++] = {"CONNECTING", colors::kWarn};
    if (s.telemetry.state && s.telemetry.state->emergency)
        warnings[n_warn++] = {"EMERGENCY", colors::kBad};
    if (bat_low) warnings[n_warn++] = {"LOW BATTERY", colors::kBad};
    float wy = tape_y + tape_h + fs * 2.0f;
    for (std::size_t i = 0; i < n_warn; ++i) {
        const auto [w, col] = warnings[i];
        const float big = fs * 1.7f;
        const ImVec2 ts = text_size(w, big);
        const ImVec2 b0{c.x - ts.x * 0.5f - 10, wy}, b1{c.x + ts.x * 0.5f + 10, wy + ts.y + 4};
        dl->AddRectFilled(b0, b1, IM_COL32(0, 0, 0, 170), 3.0f);
        dl->AddRect(b0, b1, col, 3.0f, 0, 2.0f);
        text(dl, {b0.x + 10, b0.y + 2}, col, w, big);
        wy = b1.y + 4;
    }
    // ---- The assist: what it does and why, under the warnings -------------------------------
    const AssistView& as = s.assist;
    if (as.available) {
        const bool say =
            as.acting || as.unknown || as.confirming || as.override_held || !as.enabled;
        std::string_view msg =
            say ? std::string_view(as.line) : (as.dry_run ? "ASSIST (dry run)" : "ASSIST ON");
        const std::uint32_t col = as.acting                                         ? colors::kBad
                                  : as.unknown || as.confirming || as.override_held ? colors::kWarn
                                  : !as.enabled                                     ? colors::kWarn
                                                                                    : colors::kGood;
        float size = say ? fs * 1.35f : fs * 0.9f;
        // Wider than the picture (a long PROBING line on a small window): broken at spaces into
        // lines that fit, each centred, never cut off at the picture's edges. At spaces only:
        // ImGui's own word wrap also breaks after a '.', which would split "0.41 m/s".
        // When so wrapped it reaches down to the speed and altitude read-outs (a small window),
        // it is wrapped again into the column between them: the pilot reads both.
        std::array<BannerLine, kMaxBannerLines> wrapped;
        std::size_t n_lines = 0;
        float tw = 0, th = 0;
        const auto wrap = [&](float max_w) {
            n_lines = wrap_at_spaces(msg, size, max_w, wrapped);
            tw = th = 0;
            for (std::size_t i = 0; i < n_lines; ++i) {
                tw = std::max(tw, wrapped[i].w);
                th += wrapped[i].h;
            }
        };
        const auto box = [&] {
            return Rect{c.x - tw * 0.5f - 8, wy, c.x + tw * 0.5f + 8, wy + th + 4};
        };
        const auto lay_out = [&] {
            wrap(std::max(fs * 4.0f, W - 40.0f));
            bool covers = false;
            for (const Rect& r : readouts) covers = covers || overlaps(box(), r);
            if (covers) {
                // The column, and the banner in it: in the larger type if it fits there whole,
                // else in the body type (a small picture).
                const float column = 2.0f * std::min(c.x - std::max(readouts[0].x1, readouts[1].x1),
                                                     readouts[2].x0 - c.x);
                const float max_w = std::max(fs * 4.0f, column - 24.0f);
                wrap(max_w);
                if (tw > max_w || n_lines == kMaxBannerLines || box().y1 > p1.y) {
                    size = std::min(size, fs);
                    wrap(max_w);
                }
            }
        };
        lay_out();
        // Still running out of the picture (a small one, a long line: a side's steering with a
        // brake pending behind it), whose end would be cut off: the action words alone, which
        // say both ("STEERING LEFT; BRAKE PENDING"); the status bar's tooltip keeps the line.
        if (say && box().y1 > p1.y && !as.brief.empty()) {
            msg = as.brief;
            size = fs * 1.35f;
            lay_out();
        }
        const Rect bx = box();
        const ImVec2 b0{bx.x0, bx.y0}, b1{bx.x1, bx.y1};
        dl->AddRectFilled(b0, b1, IM_COL32(0, 0, 0, say ? 170 : 110), 3.0f);
        if (say) dl->AddRect(b0, b1, col, 3.0f, 0, 2.0f);
        float ly = b0.y + 2;
        for (std::size_t i = 0; i < n_lines; ++i) {
            text(dl, {c.x - wrapped[i].w * 0.5f, ly}, col, wrapped[i].text, size);
            ly += wrapped[i].h;
        }
        v.layout.assist.hud = msg;
        v.layout.labels.push_back({"hud.assist", {b0.x, b0.y, b1.x, b1.y}});
    }
    dl->PopClipRect();
}

}  // namespace gs::ui
