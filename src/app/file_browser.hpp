#pragma once
#include <functional>
#include <string>
#include <vector>

namespace sdfgen::app {

// A modal ImGui file dialog: the current folder's subfolders and the files with one of the given
// extensions. A click selects an entry, a double click or Enter opens it (enters a folder, ".."
// goes up; chooses a file); up and down move the selection; Escape closes the dialog; a name
// box for a new name. (No Debian package offers a native dialog without a toolkit.)
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
    const std::string& folder() const { return folder_; }
    // Called after each of the dialog's items with its name ("browse_entry_N", "browse_name",
    // "browse_confirm", "browse_cancel"): the GUI test's hook.
    std::function<void(const std::string&)> onItem;

private:
    void list();
    std::string entry(int i) const;
    bool activate(int i);

    std::string title_, folder_, chosen_, error_, confirm_;
    char name_[512] = "";
    std::vector<std::string> extensions_, folders_, files_;
    bool open_ = false, justOpened_ = false;
    int selected_ = -1; // the entry selected: 0 "../", then the folders, then the files
};

} // namespace sdfgen::app
