#include "app/file_browser.hpp"
#include "app/wrapped_text.hpp"
#include "core/runtime/file_extension.hpp"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>

namespace sdfgen::app {

namespace fs = std::filesystem;

void FileBrowser::open(const std::string& title, const std::string& start, std::vector<std::string> extensions, const std::string& confirm) {
    std::error_code ec;
    fs::path path = fs::absolute(start.empty() ? fs::current_path(ec) : fs::path(start), ec);
    fs::path folder = fs::is_directory(path, ec) ? path : path.parent_path();
    if (!fs::is_directory(folder, ec)) folder = fs::current_path(ec);
    title_ = title;
    folder_ = folder.lexically_normal().string();
    std::snprintf(name_, sizeof(name_), "%s", fs::is_directory(path, ec) ? "" : path.filename().string().c_str());
    extensions_ = std::move(extensions);
    confirm_ = confirm;
    open_ = justOpened_ = true;
    chosen_.clear();
    selected_ = -1;
    list();
}

void FileBrowser::list() {
    folders_.clear();
    files_.clear();
    error_.clear();
    std::error_code ec;
    for (fs::directory_iterator it(folder_, fs::directory_options::skip_permission_denied, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.empty() || name[0] == '.') continue;
        std::error_code typeError;
        if (it->is_directory(typeError)) {
            folders_.push_back(name);
            continue;
        }
        const std::string extension = lowerExtension(it->path());
        if (extensions_.empty() || std::find(extensions_.begin(), extensions_.end(), extension) != extensions_.end()) files_.push_back(name);
    }
    if (ec) error_ = folder_ + ": " + ec.message();
    std::sort(folders_.begin(), folders_.end());
    std::sort(files_.begin(), files_.end());
}

// One entry of the list: "../", the folders, then the files.
std::string FileBrowser::entry(int i) const {
    if (i == 0) return "../";
    if (i <= int(folders_.size())) return folders_[std::size_t(i - 1)] + "/";
    return files_[std::size_t(i - 1) - folders_.size()];
}

// Opens entry i: a folder is entered, a file chosen. Returns true for a file.
bool FileBrowser::activate(int i) {
    if (i < 0 || i > int(folders_.size() + files_.size())) return false;
    if (i <= int(folders_.size())) {
        folder_ = (i == 0 ? fs::path(folder_).parent_path() : fs::path(folder_) / folders_[std::size_t(i - 1)]).lexically_normal().string();
        list();
        return false;
    }
    std::snprintf(name_, sizeof(name_), "%s", entry(i).c_str());
    return true;
}

bool FileBrowser::draw() {
    if (!open_) return false;
    if (justOpened_) {
        ImGui::OpenPopup(title_.c_str());
        justOpened_ = false;
    }
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowSize(ImVec2(std::min(display.x * 0.9f, 640.0f), std::min(display.y * 0.85f, 520.0f)), ImGuiCond_Always);
    ImGui::SetNextWindowPos(ImVec2(display.x * 0.5f, display.y * 0.5f), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    bool chose = false;
    if (!ImGui::BeginPopupModal(title_.c_str(), nullptr, ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove)) {
        open_ = false;
        return false;
    }
    // Keys (while the name box is not being typed in): up and down move the selection, Enter opens
    // it (enters a folder, chooses a file); Escape closes the dialog, also from the name box.
    const int count = 1 + int(folders_.size() + files_.size());
    const bool typing = ImGui::GetIO().WantTextInput;
    bool keyMoved = false, activate = false;
    if (!typing) {
        if (ImGui::IsKeyPressed(GLFW_KEY_DOWN)) selected_ = std::min(selected_ + 1, count - 1), keyMoved = true;
        if (ImGui::IsKeyPressed(GLFW_KEY_UP)) selected_ = std::max(selected_ - 1, 0), keyMoved = true;
        if (ImGui::IsKeyPressed(GLFW_KEY_ENTER) || ImGui::IsKeyPressed(GLFW_KEY_KP_ENTER)) {
            activate = selected_ >= 0;
            chose = selected_ < 0 && name_[0] != '\0'; // nothing selected: the name's file, as the button does
        }
        if (keyMoved && selected_ > int(folders_.size())) std::snprintf(name_, sizeof(name_), "%s", entry(selected_).c_str());
    }
    const bool escape = ImGui::IsKeyPressed(GLFW_KEY_ESCAPE);
    wrappedText("%s", folder_.c_str());
    const float footer = ImGui::GetFrameHeightWithSpacing() * 2.0f + ImGui::GetTextLineHeightWithSpacing();
    ImGui::BeginChild("##entries", ImVec2(0, -footer), true);
    // A click selects, a double click opens.
    int open = -1;
    for (int i = 0; i < count; ++i) {
        const std::string label = entry(i);
        if (ImGui::Selectable(label.c_str(), i == selected_, ImGuiSelectableFlags_AllowDoubleClick)) {
            selected_ = i;
            if (i > int(folders_.size())) std::snprintf(name_, sizeof(name_), "%s", label.c_str());
            if (ImGui::IsMouseDoubleClicked(0)) open = i;
        }
        if (keyMoved && i == selected_) ImGui::SetScrollHereY();
        if (onItem) onItem("browse_entry_" + std::to_string(i) + (i == selected_ ? "_selected" : ""));
    }
    ImGui::EndChild();
    if (activate) open = selected_;
    if (open >= 0) {
        const std::string before = folder_;
        chose = this->activate(open);
        if (folder_ != before) selected_ = -1; // a new folder: nothing selected yet
    }
    if (!error_.empty()) ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.35f, 1.0f), "%s", error_.c_str());
    else {
        std::string kinds;
        for (const std::string& e : extensions_) kinds += (kinds.empty() ? "" : " ") + e;
        ImGui::TextDisabled("%zu folders, %zu files (%s)", folders_.size(), files_.size(), kinds.c_str());
    }
    ImGui::SetNextItemWidth(-1.0f);
    if (ImGui::InputText("##name", name_, sizeof(name_), ImGuiInputTextFlags_EnterReturnsTrue)) chose = true;
    if (onItem) onItem("browse_name");
    if (ImGui::Button(confirm_.c_str())) {
        // A folder selected: enter it; otherwise the name's file.
        if (selected_ >= 0 && selected_ <= int(folders_.size())) {
            this->activate(selected_);
            selected_ = -1;
        } else {
            chose = true;
        }
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel") || escape) {
        open_ = false;
        chose = false;
        ImGui::CloseCurrentPopup();
    }
    if (chose && open_ && name_[0] != '\0') {
        chosen_ = (fs::path(folder_) / name_).string();
        open_ = false;
        ImGui::CloseCurrentPopup();
    } else {
        chose = false;
    }
    ImGui::EndPopup();
    return chose;
}

} // namespace sdfgen::app
