#include "ui/windows.hpp"

#include <cstdio>

namespace gs::ui {

void MessagesWindow::draw(const GuiSnapshot& s, ViewState& v) {
    if (!ImGui::Begin("Messages", &v.open.messages)) {
        ImGui::End();
        return;
    }
    if (ImGui::BeginChild("##log", {0, 0}, false, ImGuiWindowFlags_HorizontalScrollbar)) {
        for (const LogLine& m : s.messages) {
            std::uint32_t col = colors::kText;
            const char* tag = "";
            switch (m.level) {
                case LogLevel::Ok:
                    col = colors::kGood;
                    break;
                case LogLevel::Warn:
                    col = colors::kWarn;
                    tag = "! ";
                    break;
                case LogLevel::Error:
                    col = colors::kBad;
                    tag = "!! ";
                    break;
                case LogLevel::Info:
                    break;
            }
            if (known(m.t_s))
                ImGui::TextColored(colors::v4(colors::kDim), "%8.1f s", m.t_s);
            else
                ImGui::TextColored(colors::v4(colors::kDim), "%10s", "");
            ImGui::SameLine();
            ImGui::TextColored(colors::v4(col), "%s%s", tag, m.text.c_str());
        }
        // Opened from the status bar, or already at the end: follow the newest line.
        if (v.messages_scroll_to_end || ImGui::GetScrollY() >= ImGui::GetScrollMaxY() - 1.0f) {
            ImGui::SetScrollHereY(1.0f);
            v.messages_scroll_to_end = false;
        }
        v.layout.messages_at_end = ImGui::GetScrollY() >= ImGui::GetScrollMaxY() - 1.0f;
        v.layout.messages_shown = static_cast<int>(s.messages.size());
    }
    ImGui::EndChild();
    ImGui::End();
}

}  // namespace gs::ui
