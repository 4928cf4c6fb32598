#pragma once
// The ground-station windows: one struct per window, one .cpp each (docs/style.md rule 22). Each
// draws the snapshot, keeps its state in ViewState, and writes requests into Actions. Always
// Begin/End paired; default position/size from the default layout (FirstUseEver, then imgui.ini).

#include "ui/actions.hpp"
#include "ui/controls.hpp"
#include "ui/layout.hpp"
#include "ui/snapshot.hpp"
#include "ui/view_state.hpp"

#include <imgui.h>

#include <string>
#include <vector>

namespace gs::ui {

// Gives the window a texture for the current video frame (GL in the app, a stub in tests).
class TextureSource {
public:
    virtual ~TextureSource() = default;
    // Texture holding `frame` (uploaded once per new frame index). nullptr if none.
    virtual ImTextureID video_texture(const VideoFrame& frame) = 0;
};

// Shared colours, so every window says "bad" and "good" the same way.
namespace colors {
inline constexpr std::uint32_t kGood = IM_COL32(70, 200, 100, 255);
inline constexpr std::uint32_t kWarn = IM_COL32(245, 175, 40, 255);
inline constexpr std::uint32_t kBad = IM_COL32(235, 65, 55, 255);
inline constexpr std::uint32_t kInfo = IM_COL32(110, 170, 240, 255);
inline constexpr std::uint32_t kDim = IM_COL32(150, 155, 162, 255);
inline constexpr std::uint32_t kText = IM_COL32(225, 228, 232, 255);
// A still camera's region (RegionBar::still): measured, but not for what stands ahead.
inline constexpr std::uint32_t kStill = IM_COL32(70, 130, 190, 255);
ImVec4 v4(std::uint32_t c);
}  // namespace colors

// A measured region whose score is over its threshold but which the classifier has not flagged
// (it waits for its confirmation frames): shown amber "confirming", never green "clear".
inline bool confirming(bool known_now, bool flagged, double score, double threshold) {
    return known_now && !flagged && known(score) && known(threshold) && score > threshold;
}
// What a region's bar and its line in the Classifier window show, in the order that decides it:
// no data (unknown or stale: grey, never green), UNSAFE, confirming (amber), still (steel blue:
// nothing approaching, what stands ahead not judged), clear.
enum class RegionShown : std::uint8_t { NoData, Unsafe, Confirming, Still, Clear };
inline RegionShown region_shown(bool known_now, bool flagged, bool still, double score,
                                double threshold) {
    if (!known_now) return RegionShown::NoData;
    if (flagged) return RegionShown::Unsafe;
    if (confirming(known_now, flagged, score, threshold)) return RegionShown::Confirming;
    return still ? RegionShown::Still : RegionShown::Clear;
}
inline const char* shown_word(RegionShown s) {
    static constexpr const char* kWords[] = {"no data", "UNSAFE", "confirming", "still", "clear"};
    return kWords[static_cast<std::size_t>(s)];
}
// What a "still" region means, for its tooltip and the classifier window.
inline constexpr const char* kStillMeaning =
    "camera still: nothing is approaching, but an obstacle standing ahead is not seen until the "
    "drone moves";

struct Hud {
    // Draws the head-up display over [p0, p1] (the video image area), records the battery gauge.
    void draw(ImDrawList* dl, ImVec2 p0, ImVec2 p1, const GuiSnapshot& s, ViewState& v);
};

struct VideoWindow {
    Hud hud;
    // `fixed`: the flight layout's video, without title bar, never moved or closed.
    void draw(const GuiSnapshot& s, ViewState& v, Actions& a, TextureSource* tex,
              const char* name = "Video", bool fixed = false);
};

struct TelemetryWindow {
    void draw(const GuiSnapshot& s, ViewState& v);
};

struct LinkWindow {
    void draw(const GuiSnapshot& s, ViewState& v);
};

// Why the drone will not take off, or why it cut out, from the connection state and state bits.
enum class Severity { Blocker, Warning, Info, Ok };
struct Reason {
    Severity severity = Severity::Info;
    std::string title;   // "Battery too low"
    std::string detail;  // what it means and what to do
};
std::vector<Reason> explain_not_flying(const GuiSnapshot& s);

struct WhyNotFlyingWindow {
    void draw(const GuiSnapshot& s, ViewState& v);
};

struct PlotsWindow {
    void draw(const GuiSnapshot& s, ViewState& v);
    // The flight layout's compact strip: region scores, altitude, battery and attitude in a row.
    void draw_strip(const GuiSnapshot& s, ViewState& v);
};

struct ClassifierWindow {
    void draw(const GuiSnapshot& s, ViewState& v, Actions& a);
};

struct RecordingWindow {
    void draw(const GuiSnapshot& s, ViewState& v, Actions& a);
};

// A score beside its threshold: two significant digits of the threshold's magnitude, the score
// with as many decimals ("0.12" for 0.3, "0.0000" for 4.95e-06 against 0.0013 -> "0.0013"),
// never an exponent; "-" for NaN.
std::string format_score(double score, double threshold);

// "1.5 GB", "12.0 kB" ...
std::string format_bytes(double bytes);
// "01:02:03" / "02:03.4"
std::string format_duration(double seconds);
// `digits` significant digits, no exponent for large values ("0.0013", "0.52", "12.3", "1235");
// "-" for NaN. Scores and thresholds of any magnitude stay readable.
std::string format_sig(double v, int digits = 3);

// The replay speeds the window offers (the session's pacing accepts the same range).
inline constexpr double kReplayMinSpeed = 0.25, kReplayMaxSpeed = 8.0;

struct ReplayWindow {
    void draw(const GuiSnapshot& s, ViewState& v, Actions& a);
};

// Connection + flight controls (take off / land / emergency buttons, current pilot command).
struct ConnectionWindow {
    void draw(const GuiSnapshot& s, ViewState& v, Actions& a);
};

// Camera calibration mode on the live or replayed video: board settings, the detection status,
// capture (button or K), a coverage map, the running error and "Save and apply". Drawing only:
// the session's calibration worker detects, decides what is kept, calibrates and saves.
struct CalibrationWindow {
    void draw(const GuiSnapshot& s, ViewState& v, Actions& a, TextureSource* tex);
};

// Draws the calibration board corners (rows joined, first corner marked) over the image at
// [p0, p0 + size*scale]; returns how many corners were drawn.
int draw_board_corners(ImDrawList* dl, ImVec2 p0, float scale, const CalibrationView& c);

// Remembers the rectangle of the last ImGui item (a button) under `name` for tests.
inline void record_button(ViewState& v, const char* name) {
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    v.layout.buttons.push_back({name, {a.x, a.y, b.x, b.y}});
}

// After a control's button: when the control cannot act, records `why` in the layout report
// (v.layout.disabled) and shows it as the tooltip while the disabled button is hovered.
void note_disabled(ViewState& v, const char* id, const ControlState& cs);

// A button that requests `c` (sets `out` when clicked), disabled with its reason while the
// control cannot act; the button is recorded under `id` and `label` is what it shows.
void command_button(ViewState& v, const GuiSnapshot& s, const char* id, const std::string& label,
                    Control c, bool& out);

// Key help.
struct KeysWindow {
    void draw(ViewState& v);
};

// The fixed status bar under the menu bar (ui/status_bar.cpp): source, flight state, battery,
// link, video, REC, the flight buttons, banners and the latest message.
struct StatusBar {
    void draw(const GuiSnapshot& s, ViewState& v, Actions& a);
};

// Drone -> Settings: the drone's flight limits, indoor/outdoor and hull, video and navdata
// rate, written with the link's SetConfig (multiconfiguration ids) and confirmed by reading the
// configuration back; magnetometer calibration (flying) and flat trim (landed).
struct DroneSettingsWindow {
    void draw(const GuiSnapshot& s, ViewState& v, Actions& a);
};

// The flight layout: the video with its overlay and HUD filling the window under the status
// bar, a compact plot strip below.
struct FlightView {
    VideoWindow video;
    PlotsWindow plots;
    void draw(const GuiSnapshot& s, ViewState& v, Actions& a, TextureSource* tex);
};

// The message log, newest last, scrolled to the newest when opened from the status bar.
struct MessagesWindow {
    void draw(const GuiSnapshot& s, ViewState& v);
};

}  // namespace gs::ui
