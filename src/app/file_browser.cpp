#include "app/file_browser.hpp"
#include "app/wrapped_text.hpp"
#include "core/io/file_extension.hpp"

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
    wrappedText("%s", folder_.c_str());
    const float footer = ImGui::GetFrameHeightWithSpacing() * 2.0f + ImGui::GetTextLineHeightWithSpacing();
    ImGui::BeginChild("##entries", ImVec2(0, -footer), true);
    std::string enter;
    if (ImGui::Selectable("../")) enter = fs::path(folder_).parent_path().string();
    for (const std::string& f : folders_) {
        if (ImGui::Selectable((f + "/").c_str())) enter = (fs::path(folder_) / f).string();
    }
    for (const std::string& f : files_) {
        if (ImGui::Selectable(f.c_str(), f == name_, ImGuiSelectableFlags_AllowDoubleClick)) {
            std::snprintf(name_, sizeof(name_), "%s", f.c_str());
            if (ImGui::IsMouseDoubleClicked(0)) chose = true;
        }
    }
    ImGui::EndChild();
    if (!enter.empty()) {
        folder_ = fs::path(enter).lexically_normal().string();
        list();
    }
    if (!error_.empty()) ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.35f, 1.0f), "%s", error_.c_str());
    else {
        std::string kinds;
        for (const std::string& e : extensions_) kinds += (kinds.empty() ? "" : " ") + e;
        ImGui::TextDisabled("%zu folders, %zu files (%s)", folders_.size(), files_.size(), kinds.c_str());
    }
    ImGui::SetNextItemWidth(-1.0f);
    if (ImGui::InputText("##name", name_, sizeof(name_), ImGuiInputTextFlags_EnterReturnsTrue)) chose = true;
    if (ImGui::Button(confirm_.c_str())) chose = true;
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) {
        open_ = false;
        ImGui::CloseCurrentPopup();
    }
    if (chose && name_[0] != '\0') {
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
