#pragma once
#include <cstddef>
#include <string>

namespace sdfgen {

// What a mesh check found. Pseudonormal signs are provably right only when every count is zero.
struct MeshCheck {
    std::size_t boundaryEdges = 0;       // edges with one triangle: the mesh has holes
    std::size_t nonManifoldEdges = 0;    // edges with three or more triangles
    std::size_t inconsistentEdges = 0;   // edges whose two triangles run the same way: flipped faces
    std::size_t nonManifoldVertices = 0; // vertices whose triangles form several fans (pinches)
    std::size_t selfIntersections = 0;   // pairs of triangles with a common point beyond shared vertices (exact)
    // False when the (costly) search for self-intersections was skipped: sign auto skips it when the
    // edges already rule the pseudonormal out. selfIntersections is then 0 and means nothing.
    bool selfIntersectionsSearched = true;
    double signedVolume = 0;             // enclosed by the triangles as oriented (negative: they face inwards)
    // Closed shells (connected parts) whose facing does not fit their nesting, when every other count
    // is zero (searched with the self-intersections): a part inside out beside parts that face
    // outwards, or a shell inside another that faces the same way. The pseudonormal sign follows the
    // faces and would get such a part wrong (flipping it whole cannot help), so auto takes the
    // winding sign, which counts every closed part solid (|w| > 1/2) and a reversed inner shell's
    // cavity empty. A hollow part (an inner shell facing into its cavity) fits its nesting.
    std::size_t misorientedShells = 0;
    // Closed, manifold along edges and consistently oriented, but with negative volume: every face
    // points inwards. When sign auto picks the pseudonormal it then swaps inside and outside, as if
    // the faces were flipped; the winding sign (|w| > 1/2) needs no swap.
    bool insideOut = false;

    bool closedAndClean() const {
        return boundaryEdges + nonManifoldEdges + inconsistentEdges + nonManifoldVertices + selfIntersections + misorientedShells == 0;
    }
    // "12 boundary edges, 0 non-manifold edges, ..." for summaries and the panel.
    std::string describe() const;
};

} // namespace sdfgen
