// The registry of views, in drawing order (each pass draws them in this order). A new view: its
// file view_NAME.cpp and its two lines here.
#include "render/view.hpp"

namespace sdfgen::render {

extern const ViewType kMeshView, kWireView, kSliceView, kRaymarchView, kBoxView, kGridView, kVolumeView, kSignErrorsView;

const std::vector<ViewType>& viewTypes() {
    static const std::vector<ViewType> types = {kMeshView, kWireView, kSliceView, kRaymarchView, kBoxView, kGridView, kVolumeView, kSignErrorsView};
    return types;
}

} // namespace sdfgen::render
