#include "ui/windows.hpp"

#include <cstdio>

namespace gs::ui {

void LinkWindow::draw(const GuiSnapshot& s, ViewState& v) {
    if (!ImGui::Begin("Link", &v.open.link)) {
        ImGui::End();
        return;
    }
    // Columns as wide as their content (never cut); a narrow window scrolls sideways instead.
    const ImGuiTableFlags tf = ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV |
                               ImGuiTableFlags_SizingFixedFit | ImGuiTableFlags_ScrollX;
    const StreamHealth* streams[] = {&s.link.navdata, &s.link.video, &s.link.at};
    const char* names[] = {"navdata", "video", "AT"};
    const float table_h = ImGui::GetTextLineHeightWithSpacing() * 11.5f;
    if (ImGui::BeginTable("health", 4, tf, {0, table_h})) {
        ImGui::TableSetupColumn("", ImGuiTableColumnFlags_WidthFixed);  // labels in full
        for (const char* n : names) ImGui::TableSetupColumn(n);
        ImGui::TableHeadersRow();
        auto rowf = [&](const char* label, auto get, auto bad) {
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(0);
            ImGui::TextColored(colors::v4(colors::kDim), "%s", label);
            for (int c = 0; c < 3; ++c) {
                ImGui::TableSetColumnIndex(c + 1);
                const StreamHealth& h = *streams[c];
                const std::string txt = h.active ? get(h) : std::string("-");
                ImGui::TextColored(colors::v4(h.active && bad(h) ? colors::kWarn
                                              : h.active         ? colors::kText
                                                                 : colors::kDim),
                                   "%s", txt.c_str());
            }
        };
        auto fmt = [](int decimals, double x, const char* unit) {
            char b[48];
            if (!known(x)) return std::string("?");
            std::snprintf(b, sizeof b, "%.*f %s", decimals, x, unit);
            return std::string(b);
        };
        auto cnt = [](std::uint64_t x) { return std::to_string(x); };
        rowf(
            "rate /s", [&](const StreamHealth& h) { return fmt(1, h.rate_hz, ""); },
            [](const StreamHealth&) { return false; });
        rowf(
            "age", [&](const StreamHealth& h) { return fmt(0, h.age_ms, "ms"); },
            [](const StreamHealth& h) { return known(h.age_ms) && h.age_ms > 500; });
        rowf(
            "bytes /s", [&](const StreamHealth& h) { return format_bytes(h.bytes_per_s); },
            [](const StreamHealth&) { return false; });
        rowf(
            "packets", [&](const StreamHealth& h) { return cnt(h.packets); },
            [](const StreamHealth&) { return false; });
        rowf(
            "gaps", [&](const StreamHealth& h) { return cnt(h.gaps); },
            [](const StreamHealth& h) { return h.gaps > 0; });
        rowf(
            "drops", [&](const StreamHealth& h) { return cnt(h.drops); },
            [](const StreamHealth& h) { return h.drops > 0; });
        rowf(
            "bad checksum", [&](const StreamHealth& h) { return cnt(h.checksum_failures); },
            [](const StreamHealth& h) { return h.checksum_failures > 0; });
        rowf(
            "decode errors", [&](const StreamHealth& h) { return cnt(h.decode_errors); },
            [](const StreamHealth& h) { return h.decode_errors > 0; });
        rowf(
            "IDR waits", [&](const StreamHealth& h) { return cnt(h.idr_waits); },
            [](const StreamHealth& h) { return h.idr_waits > 0; });
        ImGui::EndTable();
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(colors::v4(colors::kDim),
                           "rate: navdata packets, video frames, AT datagrams");
        ImGui::PopTextWrapPos();
    }
    ImGui::TextColored(
        colors::v4(colors::kDim), "UI %.1f ms/frame (%.0f fps), classifier %s",
        known(v.ui_frame_ms) ? v.ui_frame_ms : 0.0, known(v.ui_fps) ? v.ui_fps : 0.0,
        known(s.classifier.cycle_ms)
            ? (std::to_string(static_cast<int>(s.classifier.cycle_ms + 0.5)) + " ms").c_str()
            : "-");
    if (ImGui::SmallButton("Messages...")) v.open.messages = true;
    ImGui::End();
}

}  // namespace gs::ui
