// The registry of views, in drawing order (each pass draws them in this order): one line per
// view, naming the ViewType its file view_NAME.cpp defines.
#include "render/view.hpp"
#include "sdfgen/error.hpp"

#include <algorithm>
#include <sstream>

#define SDFGEN_VIEWS(VIEW) \
    VIEW(kMeshView)        \
    VIEW(kWireView)        \
    VIEW(kSliceView)       \
    VIEW(kRaymarchView)    \
    VIEW(kBoxView)         \
    VIEW(kGridView)        \
    VIEW(kVolumeView)      \
    VIEW(kSignErrorsView)  \
    // the list's end: each line above ends with a backslash

namespace sdfgen::render {

#define SDFGEN_DECLARE_VIEW(type) extern const ViewType type;
SDFGEN_VIEWS(SDFGEN_DECLARE_VIEW)

const std::vector<ViewType>& viewTypes() {
#define SDFGEN_LIST_VIEW(type) type,
    static const std::vector<ViewType> types = {SDFGEN_VIEWS(SDFGEN_LIST_VIEW)};
    return types;
}

View::View(const ViewType& type) : enabled(type.shownByDefault), type_(type) {}

std::string viewNames() {
    std::string text;
    for (const ViewType& type : viewTypes()) text += (text.empty() ? "" : ", ") + std::string(type.name);
    return text;
}

std::vector<bool> parseViewList(const std::string& list) {
    const std::vector<ViewType>& types = viewTypes();
    std::vector<bool> shown(types.size(), false);
    std::stringstream in(list);
    std::string word;
    while (std::getline(in, word, ',')) {
        if (word == "all") {
            std::fill(shown.begin(), shown.end(), true);
            continue;
        }
        if (word == "none" || word.empty()) continue;
        const auto found = std::find_if(types.begin(), types.end(), [&](const ViewType& type) { return word == type.name; });
        if (found == types.end()) throw Error("unknown view '" + word + "' (expected " + viewNames() + ", all or none)");
        shown[std::size_t(found - types.begin())] = true;
    }
    return shown;
}

} // namespace sdfgen::render
