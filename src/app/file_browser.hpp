#pragma once
#include <string>
#include <vector>

namespace sdfgen::app {

// A modal ImGui file dialog: the current folder's subfolders and the files with one of the given
// extensions; click a folder to enter it, ".." to go up, a file to choose it; a name box for a
// new name. (No Debian package offers a native dialog without a toolkit.)
class FileBrowser {
public:
    // Opens at the folder of `start` (the working folder when it has none or does not exist); the
    // confirm button says `confirm` ("Open", "Choose": what choosing does).
    void open(const std::string& title, const std::string& start, std::vector<std::string> extensions, const std::string& confirm);
    // Draws the dialog while open; returns true once when a file was chosen (see chosen()).
    bool draw();
    bool isOpen() const { return open_; }
    const std::string& chosen() const { return chosen_; }
    const std::string& title() const { return title_; }

private:
    void list();

    std::string title_, folder_, chosen_, error_, confirm_;
    char name_[512] = "";
    std::vector<std::string> extensions_, folders_, files_;
    bool open_ = false, justOpened_ = false;
};

} // namespace sdfgen::app
