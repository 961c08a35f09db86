// mergeMeshes: a scene of placed meshes as one soup, whose field is the union of the solids.
#include "sdfgen/error.hpp"
#include "sdfgen/field_match.hpp"
#include "sdfgen/mesh.hpp"

#include "support/checks.hpp"
#include "support/shapes.hpp"

#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <algorithm>
#include <cmath>

namespace sdfgen {
namespace {

TEST(MergeMeshes, TransformsEveryPartAndKeepsTheirTriangles) {
    const Mesh box = test::box(glm::vec3(0.5f));
    const Mesh ball = test::icosphere(0.5f, 2);
    const glm::dmat4 moved = glm::scale(glm::translate(glm::dmat4(1.0), glm::dvec3(3, 0, 0)), glm::dvec3(2.0));
    const Mesh scene = mergeMeshes({{&box, glm::dmat4(1.0)}, {&ball, moved}}, "box+ball");
    EXPECT_EQ(scene.source, "box+ball");
    EXPECT_EQ(scene.triangleCount(), box.triangleCount() + ball.triangleCount());
    EXPECT_NEAR(scene.worldBounds().min.x, -0.5f, 1e-6f);
    EXPECT_NEAR(scene.worldBounds().max.x, 4.0f, 1e-5f); // the ball scaled to radius 1 about (3, 0, 0)
    EXPECT_NEAR(scene.worldBounds().max.y, 1.0f, 1e-5f);
}

TEST(MergeMeshes, MirroredPartsKeepOutwardNormals) {
    const Mesh box = test::box(glm::vec3(0.5f, 0.3f, 0.2f));
    const glm::dmat4 mirror = glm::scale(glm::dmat4(1.0), glm::dvec3(-1.0, 1.0, 1.0));
    const Mesh scene = mergeMeshes({{&box, mirror}}, "mirrored");
    ASSERT_EQ(scene.triangleCount(), box.triangleCount());
    for (std::size_t t = 0; t < scene.triangleCount(); ++t) {
        const glm::vec3 centroid = (scene.vertex(t, 0) + scene.vertex(t, 1) + scene.vertex(t, 2)) / 3.0f;
        EXPECT_GT(glm::dot(scene.faceNormals[t], centroid), 0.0f) << "triangle " << t << " faces inwards";
    }
}

TEST(MergeMeshes, BadScenesAreErrors) {
    EXPECT_CONTAINS(test::errorFrom([] { mergeMeshes({}, "empty"); }), "at least one mesh");
    const Mesh box = test::box(glm::vec3(0.5f));
    glm::dmat4 broken(1.0);
    broken[3][0] = std::nan("");
    EXPECT_CONTAINS(test::errorFrom([&] { mergeMeshes({{&box, broken}}, "nan"); }), "non-finite");
}

// The union of two overlapping boxes and a separate ball: |distance| is the nearest of the three
// surfaces (every triangle counts), and a sample is inside when it is inside any part.
TEST(MergeMeshes, BakesTheUnionOfTheParts) {
    const glm::vec3 half(0.5f);
    const Mesh box = test::box(half);
    const Mesh ball = test::icosphere(0.4f, 3);
    const glm::dvec3 second(0.6, 0.2, 0.0), third(-1.2, 0.0, 0.3);
    const Mesh scene = mergeMeshes({{&box, glm::dmat4(1.0)},
                                    {&box, glm::translate(glm::dmat4(1.0), second)},
                                    {&ball, glm::translate(glm::dmat4(1.0), third)}},
                                   "union");
    BakeSettings settings;
    settings.res = 24;
    settings.sign = SignMethod::Winding;
    const Field field = test::bakeMesh(scene, settings).field.dense();
    const float sag = test::icosphereSag(0.4f, 3);
    int checked = 0;
    for (int k = 0; k < field.grid.dims.z; ++k) {
        for (int j = 0; j < field.grid.dims.y; ++j) {
            for (int i = 0; i < field.grid.dims.x; ++i) {
                const glm::vec3 p(field.grid.position(i, j, k));
                const float a = test::boxDistance(p, half), b = test::boxDistance(p - glm::vec3(second), half);
                const float c = test::sphereDistance(p - glm::vec3(third), 0.4f);
                const float nearest = std::min({std::abs(a), std::abs(b), std::abs(c)});
                const float value = field.at(i, j, k);
                EXPECT_NEAR(std::abs(value), nearest, sag + 1e-5f) << "at " << p.x << " " << p.y << " " << p.z;
                if (nearest > sag + 1e-4f) {
                    EXPECT_EQ(value < 0.0f, a < 0.0f || b < 0.0f || c < 0.0f) << "sign at " << p.x << " " << p.y << " " << p.z;
                    ++checked;
                }
            }
        }
    }
    EXPECT_GT(checked, 1000);
}

TEST(FieldMismatch, NamesAnotherSourceOrAGridThatDoesNotCover) {
    Mesh box = test::box(glm::vec3(0.5f));
    box.source = "models/box.obj";
    BakeSettings settings;
    settings.res = 8;
    Field field = test::bakeMesh(box, settings).field.dense();
    field.source = "elsewhere/box.obj"; // the same file name in another folder still matches
    EXPECT_EQ(fieldMismatch(field, box), "");
    field.source = "ball.obj";
    EXPECT_EQ(fieldMismatch(field, box), "the field was made from ball.obj, not from box.obj");
    field.grid.origin.x += 0.3f; // no longer covers the box: both are said
    EXPECT_EQ(fieldMismatch(field, box), "the field was made from ball.obj, not from box.obj, and its grid does not cover the model");
    field.source = "box.obj";
    EXPECT_CONTAINS(fieldMismatch(field, box), "does not cover the model");
}

} // namespace
} // namespace sdfgen
