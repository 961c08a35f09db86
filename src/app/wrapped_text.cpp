#include "app/wrapped_text.hpp"

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

namespace sdfgen::app {

void wrappedText(const char* format, ...) {
    va_list args;
    va_start(args, format);
    va_list copy;
    va_copy(copy, args);
    std::string text(std::size_t(std::max(std::vsnprintf(nullptr, 0, format, copy), 0)), '\0');
    va_end(copy);
    std::vsnprintf(text.data(), text.size() + 1, format, args);
    va_end(args);
    const float width = std::max(ImGui::GetContentRegionAvail().x, ImGui::GetFontSize());
    auto fits = [&](const std::string& line) { return ImGui::CalcTextSize(line.c_str()).x <= width; };
    std::vector<std::string> lines;
    std::stringstream paragraphs(text);
    for (std::string paragraph; std::getline(paragraphs, paragraph);) {
        std::stringstream words(paragraph);
        std::string line;
        for (std::string word; words >> word;) {
            if (!line.empty() && fits(line + " " + word)) {
                line += " " + word;
                continue;
            }
            if (!line.empty()) lines.push_back(line);
            line = word;
            while (!fits(line)) {
                std::size_t end = 1; // the longest head that fits (at least a character)
                while (end < line.size() && fits(line.substr(0, end + 1))) ++end;
                const std::size_t slash = line.rfind('/', end - 1);
                if (slash != std::string::npos && slash > 0) end = slash + 1;
                lines.push_back(line.substr(0, end));
                line.erase(0, end);
            }
        }
        lines.push_back(line);
    }
    if (lines.empty()) lines.emplace_back(); // an empty text is still an item
    // The lines as tight as one wrapped text; the usual spacing after the last.
    for (std::size_t i = 0; i < lines.size(); ++i) {
        if (i + 1 < lines.size()) ImGui::PushStyleVar(ImGuiStyleVar_ItemSpacing, ImVec2(ImGui::GetStyle().ItemSpacing.x, 0.0f));
        ImGui::TextUnformatted(lines[i].c_str());
        if (i + 1 < lines.size()) ImGui::PopStyleVar();
    }
}

} // namespace sdfgen::app
