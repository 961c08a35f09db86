#pragma once
#include <string>
#include <vector>

namespace sdfgen::app {

// The files opened recently, newest first, remembered between runs in
// $XDG_CONFIG_HOME/sdfgen/recent.txt (~/.config/sdfgen/recent.txt), one path a line, written
// atomically. A missing or unreadable file is an empty list; a failed write is reported by add().
class RecentFiles {
public:
    static constexpr std::size_t kMax = 12;
    RecentFiles();
    const std::vector<std::string>& paths() const { return paths_; }
    // Puts `path` (made absolute) first and saves the list; returns an error message or "".
    std::string add(const std::string& path);
    const std::string& file() const { return file_; }

private:
    std::string file_;
    std::vector<std::string> paths_;
};

} // namespace sdfgen::app
