#include "app/recent_files.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace sdfgen::app {

namespace fs = std::filesystem;

RecentFiles::RecentFiles() {
    const char* config = std::getenv("XDG_CONFIG_HOME");
    const char* home = std::getenv("HOME");
    fs::path folder;
    if (config && *config) folder = config;
    else if (home && *home) folder = fs::path(home) / ".config";
    else return;
    file_ = (folder / "sdfgen" / "recent.txt").string();
    std::ifstream in(file_);
    for (std::string line; std::getline(in, line) && paths_.size() < kMax;) {
        if (!line.empty()) paths_.push_back(line);
    }
}

std::string RecentFiles::add(const std::string& path) {
    std::error_code ec;
    const std::string absolute = fs::absolute(path, ec).lexically_normal().string();
    paths_.erase(std::remove(paths_.begin(), paths_.end(), absolute), paths_.end());
    paths_.insert(paths_.begin(), absolute);
    if (paths_.size() > kMax) paths_.resize(kMax);
    if (file_.empty()) return "";
    fs::create_directories(fs::path(file_).parent_path(), ec);
    const std::string temporary = file_ + ".tmp-" + std::to_string(::getpid());
    {
        std::ofstream out(temporary, std::ios::trunc);
        for (const std::string& p : paths_) out << p << '\n';
        out.flush();
        if (!out) {
            std::remove(temporary.c_str());
            return file_ + ": cannot save the recent files";
        }
    }
    if (std::rename(temporary.c_str(), file_.c_str()) != 0) {
        const std::string reason = std::strerror(errno);
        std::remove(temporary.c_str());
        return file_ + ": cannot save the recent files (" + reason + ")";
    }
    return "";
}

} // namespace sdfgen::app
