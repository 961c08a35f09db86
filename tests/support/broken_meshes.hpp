#pragma once
// Generated meshes that break the closed-mesh assumptions (holes, overlapping shells, open disks and
// cups, pinched and duplicated vertices) and the shape lists the accuracy suites loop over.
#include "sdfgen/mesh.hpp"

#include <glm/vec3.hpp>
#include <string>
#include <vector>

namespace sdfgen::test {

// `mesh` moved by `offset`, its triangles reversed when `flip`.
Mesh translated(const Mesh& mesh, const glm::vec3& offset, bool flip);
// Both meshes in one, b's indices shifted past a's vertices.
Mesh combined(const std::string& name, const Mesh& a, const Mesh& b);
// The icosphere of radius r without the triangles whose centroid has y > 0.8 r: a hole at the top.
Mesh holedSphere(float r);
// Two overlapping unit icospheres, the second one's triangles reversed when `flipSecond`.
Mesh twoShells(bool flipSecond);
// A fan of `n` triangles about `apex`, its rim a circle of radius R about `centre` in the plane
// spanned by u and v. apex == centre gives a flat disk; an apex off the plane a cone-shaped cup.
Mesh fan(const std::string& name, glm::vec3 centre, glm::vec3 apex, glm::vec3 u, glm::vec3 v, float R, int n, bool flip);
// A generic tilted frame for the disks, so that no edge lines up with a grid axis.
void tiltedFrame(glm::vec3& u, glm::vec3& v);
Mesh flatDisk();
Mesh cup(bool flip);
// Tetrahedron o, o+x, o+y, o+z (scaled by s, which may be negative: a mirror image), outward.
void addTetrahedron(std::vector<glm::vec3>& positions, std::vector<glm::uvec3>& triangles, glm::vec3 o, float s);
// Every triangle with three vertices of its own, at the same positions (as OBJ exports often do).
Mesh unshared(const Mesh& mesh);
double signedVolume(const Mesh& mesh);

struct Shape {
    std::string name;
    Mesh mesh;
    int res;
};
// Closed, clean meshes (the bundled bunny included) and open or overlapping ones, with the
// resolution each is compared at.
std::vector<Shape> closedShapes();
std::vector<Shape> openShapes();

} // namespace sdfgen::test
