#include "ui/windows.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace gs::ui {

void ReplayWindow::draw(const GuiSnapshot& s, ViewState& v, Actions& a) {
    if (!ImGui::Begin("Replay", &v.open.replay)) {
        ImGui::End();
        return;
    }
    const ReplayStatus& r = s.replay;
    // Last: the controls of an open replay come first, so they stay in view in a short window.
    auto recent_datasets = [&] {
        if (!v.settings.recent_datasets.empty()) {
            ImGui::SetNextItemWidth(-FLT_MIN);
            if (ImGui::BeginCombo("##recent", "recent datasets")) {
                for (const auto& p : v.settings.recent_datasets) {
                    if (ImGui::Selectable(p.c_str())) {
                        std::memset(v.replay_path.data(), 0, v.replay_path.size());
                        std::memcpy(v.replay_path.data(), p.data(),
                                    std::min(p.size(), v.replay_path.size() - 1));
                        a.replay_open = p;
                    }
                }
                ImGui::EndCombo();
            }
        }
    };
    const float bw = ImGui::GetFrameHeight() * 2.2f;
    ImGui::SetNextItemWidth(-bw - ImGui::GetStyle().ItemSpacing.x);
    const bool enter =
        ImGui::InputTextWithHint("##path", "dataset directory", v.replay_path.data(),
                                 v.replay_path.size(), ImGuiInputTextFlags_EnterReturnsTrue);
    record_button(v, "replay.path");
    ImGui::SameLine();
    if ((ImGui::Button("Open", {bw, 0}) || enter) && v.replay_path[0] != 0) {
        a.replay_open = std::string(v.replay_path.data());
        v.settings.add_recent(*a.replay_open);
        v.settings_dirty = true;
    }
    record_button(v, "replay.open");
    if (!r.error.empty()) ImGui::TextColored(colors::v4(colors::kBad), "%s", r.error.c_str());
    if (!r.open) {
        ImGui::TextColored(colors::v4(colors::kDim), "No dataset open.");
        recent_datasets();
        ImGui::End();
        return;
    }
    for (const auto& m : r.missing_inputs) {
        ImGui::PushStyleColor(ImGuiCol_Text, colors::v4(colors::kWarn));
        ImGui::TextWrapped("%s", m.c_str());
        ImGui::PopStyleColor();
        v.layout.replay_notes.push_back(m);
    }
    if (ImGui::Button("|<")) a.replay_seek = 0;
    ImGui::SameLine();
    if (ImGui::Button("<")) a.replay_step = -1;
    ImGui::SameLine();
    if (r.playing ? ImGui::Button("Pause", {bw * 1.2f, 0}) : ImGui::Button("Play", {bw * 1.2f, 0}))
        (r.playing ? a.replay_pause : a.replay_play) = true;
    ImGui::SameLine();
    if (ImGui::Button(">")) a.replay_step = 1;
    ImGui::SameLine();
    bool loop = r.loop;
    if (ImGui::Checkbox("Loop", &loop)) a.replay_loop = loop;
    long long frame = r.frame;
    const long long last = std::max<long long>(0, r.frame_count - 1);
    // The frame number is written on the line below, not inside the slider, where the handle
    // covered it on a narrow window.
    ImGui::SetNextItemWidth(-FLT_MIN);
    static const long long zero = 0;
    if (ImGui::SliderScalar("##seek", ImGuiDataType_S64, &frame, &zero, &last, ""))
        a.replay_seek = frame;
    record_button(v, "replay.seek");
    char position[64];
    std::snprintf(position, sizeof position, "frame %lld / %lld", static_cast<long long>(r.frame),
                  last);
    v.layout.replay_position = position;
    // Speed: a numeric field (any speed from 0.25x to 8x, typed and applied with Enter) and a
    // slider over the presets (powers of two); on the same line when both have room, else on a
    // line of their own.
    static const double speeds[] = {0.25, 0.5, 1, 2, 4, 8};
    int si = 2;  // the preset nearest the speed (on a log scale)
    for (int i = 0; i < 6; ++i)
        if (std::fabs(std::log2(speeds[i] / r.speed)) < std::fabs(std::log2(speeds[si] / r.speed)))
            si = i;
    const float field_w = ImGui::CalcTextSize("0.25x").x + ImGui::GetFontSize() * 1.5f;
    const float speed_w = field_w + ImGui::CalcTextSize("0.25x").x + ImGui::GetFontSize() * 4;
    (void)speed_w;
    ImGui::SetNextItemWidth(field_w);
    double typed = r.speed > 0 ? r.speed : 1.0;
    if (ImGui::InputDouble("##speed_value", &typed, 0.0, 0.0, "%.2fx",
                           ImGuiInputTextFlags_EnterReturnsTrue) &&
        std::isfinite(typed))
        a.replay_speed = std::clamp(typed, kReplayMinSpeed, kReplayMaxSpeed);
    {
        const ImVec2 f0 = ImGui::GetItemRectMin(), f1 = ImGui::GetItemRectMax();
        v.layout.buttons.emplace_back("replay_speed_value", Rect{f0.x, f0.y, f1.x, f1.y});
    }
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Replay speed, %.2gx to %.0fx: type a value and press Enter",
                          kReplayMinSpeed, kReplayMaxSpeed);
    ImGui::SameLine();
    // The presets, 0.25x .. 8x; the value is in the field beside (never under the handle).
    ImGui::SetNextItemWidth(-FLT_MIN);
    if (ImGui::SliderInt("##speed", &si, 0, 5, "")) a.replay_speed = speeds[si];

    if (known(r.fps) && r.fps > 0)
        ImGui::TextColored(colors::v4(colors::kDim), "%s   %s / %s  %.0f fps", position,
                           format_duration(static_cast<double>(r.frame) / r.fps).c_str(),
                           format_duration(static_cast<double>(r.frame_count) / r.fps).c_str(),
                           r.fps);
    else
        ImGui::TextColored(colors::v4(colors::kDim), "%s", position);
    recent_datasets();
    v.layout.replay_scroll_max = ImGui::GetScrollMaxY();
    ImGui::End();
}

}  // namespace gs::ui
