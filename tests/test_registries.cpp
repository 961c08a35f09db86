// The registries every front end reads its names from, and decideSign, the one place a sign is
// settled for bakes and point queries.
#include "core/bake/bake.hpp"
#include "core/accel/bvh.hpp"
#include "core/accel/topology.hpp"
#include "sdfgen/model.hpp"
#include "support/broken_meshes.hpp"
#include "support/checks.hpp"
#include "support/shapes.hpp"
#include "support/stand_in_device.hpp"

#include <gtest/gtest.h>
#include <algorithm>
#include <cctype>
#include <cstring>
#include <set>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace sdfgen {
namespace {

using namespace test;

// The name an id is written as: toString's for an enum, the id itself for a device.
template <class Id>
std::string nameOf(const Id& id) {
    if constexpr (std::is_enum_v<Id>) {
        return toString(id);
    } else {
        return id;
    }
}

template <class Id, class Parse>
void expectRoundTrips(const std::vector<Choice<Id>>& choices, Parse parse) {
    std::set<std::string> names;
    for (const Choice<Id>& choice : choices) {
        EXPECT_TRUE(names.insert(choice.name).second) << "two entries named " << choice.name;
        EXPECT_STRNE(choice.description, "") << choice.name;
        EXPECT_EQ(nameOf(choice.id), choice.name);
        EXPECT_EQ(parse(choice.name), choice.id) << choice.name;
        std::string upper = choice.name;
        for (char& c : upper) c = char(std::toupper(static_cast<unsigned char>(c)));
        EXPECT_EQ(parse(upper), choice.id) << upper;
    }
}

TEST(Registries, EveryChoiceRoundTripsThroughItsNameInAnyCase) {
    expectRoundTrips(distanceMethodChoices(), parseDistanceMethod);
    expectRoundTrips(signMethodChoices(), parseSignMethod);
    expectRoundTrips(deviceChoices(), parseDevice);
    {
        const ScopedDevice standIn(standInDevice("stand-in", true));
        expectRoundTrips(deviceChoices(), parseDevice);
    }
    // The choices are the registries' entries, in their order.
    ASSERT_EQ(distanceMethodChoices().size(), distanceMethods().size());
    for (std::size_t i = 0; i < distanceMethods().size(); ++i) EXPECT_EQ(distanceMethodChoices()[i].id, distanceMethods()[i].id);
    ASSERT_EQ(signMethodChoices().size(), signMethods().size());
    for (std::size_t i = 0; i < signMethods().size(); ++i) EXPECT_EQ(signMethodChoices()[i].id, signMethods()[i].id);
}

// What each entry declares it can do, it has the passes for.
TEST(Registries, EveryEntryHasThePassesItsCapabilitiesNeed) {
    for (const DistanceMethodPlugin& method : distanceMethods()) {
        EXPECT_TRUE(method.dense) << method.name;
        EXPECT_EQ(method.onDevice == nullptr, method.deviceMemory == nullptr) << method.name;
        EXPECT_TRUE(method.memory) << method.name;
        EXPECT_FALSE(signMethod(method.defaultSign).settles && method.fixedSign) << method.name;
    }
    for (const SignMethodPlugin& sign : signMethods()) {
        EXPECT_EQ(sign.dense == nullptr, sign.settles) << sign.name; // a settling choice has no passes
        EXPECT_EQ(sign.onDevice == nullptr, sign.deviceMemory == nullptr) << sign.name;
        EXPECT_TRUE(sign.memory) << sign.name;
        EXPECT_TRUE(!sign.bricks || sign.band == BandSigning::Own) << sign.name;
        EXPECT_FALSE(sign.settles && (sign.atPoint || sign.bricks || sign.onDevice)) << sign.name;
    }
}

TEST(Registries, AnUnknownNameIsRefusedWithEveryChoiceAndWhatItIs) {
    const std::string message = errorFrom([] { parseSignMethod("parity"); });
    EXPECT_CONTAINS(message, "unknown sign method 'parity'; known: ");
    for (const Choice<SignMethod>& choice : signMethodChoices()) {
        EXPECT_CONTAINS(message, std::string(choice.name) + " (" + choice.description + ")");
    }
    EXPECT_CONTAINS(errorFrom([] { parseDistanceMethod("magic"); }), "exact (the true distance to the nearest triangle)");
    EXPECT_CONTAINS(errorFrom([] { parseDevice("tpu"); }), "unknown device 'tpu'");
}

TEST(Registries, PointQueriesTakeTheSignsListedForThemAndRefuseTheOthersNamingThem) {
    const Model model(icosphere(1.0f, 2));
    const std::vector<double> point = {0.1, 0.2, 0.3};
    float distance = 0;
    PointQueryOutputs out;
    out.signedDistance = &distance;
    std::set<SignMethod> listed, serving;
    std::string names; // "auto, winding or pseudonormal"
    const std::vector<Choice<SignMethod>> choices = pointQuerySignChoices();
    for (std::size_t i = 0; i < choices.size(); ++i) {
        listed.insert(choices[i].id);
        names += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + std::string(choices[i].name);
    }
    for (const SignMethodPlugin& sign : signMethods()) {
        if (sign.servesPointQueries()) serving.insert(sign.id);
    }
    EXPECT_EQ(listed, serving);
    EXPECT_TRUE(listed.count(SignMethod::Auto) && !listed.count(SignMethod::Default));
    for (const Choice<SignMethod>& choice : signMethodChoices()) {
        if (listed.count(choice.id) || choice.id == SignMethod::Default) {
            model.query(point.data(), 1, out, choice.id);
            EXPECT_LT(distance, 0.0f) << choice.name; // inside the sphere
        } else {
            EXPECT_CONTAINS(errorFrom([&] { model.query(point.data(), 1, out, choice.id); }),
                            "point queries sign by " + names + ", not " + std::string(choice.name));
        }
    }
}

// Every sign that serves point queries answers them at a field's sample positions with the field's
// values, bit for bit, on a closed and an open mesh.
TEST(Registries, EveryPointQuerySignAgreesWithItsDenseBake) {
    for (const auto& [name, mesh] : {std::pair{"a sphere", icosphere(1.0f, 2)}, std::pair{"a holed sphere", holedSphere(1.0f)}}) {
        const Model model{Mesh(mesh)};
        for (const SignMethodPlugin& sign : signMethods()) {
            if (!sign.servesPointQueries()) continue;
            BakeSettings settings;
            settings.res = 12;
            settings.sign = sign.id;
            settings.device = "cpu";
            const Field field = model.bake(settings).field.dense();
            const Grid& g = field.grid;
            std::vector<double> points;
            for (int k = 0; k < g.dims.z; ++k)
                for (int j = 0; j < g.dims.y; ++j)
                    for (int i = 0; i < g.dims.x; ++i) {
                        const glm::dvec3 p = g.position(i, j, k);
                        points.insert(points.end(), {p.x, p.y, p.z});
                    }
            std::vector<float> distance(field.values.size());
            PointQueryOutputs out;
            out.signedDistance = distance.data();
            model.query(points.data(), distance.size(), out, sign.id);
            // The points in the field's order (Grid::index): the same bytes, or not.
            EXPECT_EQ(std::memcmp(distance.data(), field.values.data(), distance.size() * sizeof(float)), 0) << sign.name << " on " << name;
        }
    }
}

// Every method with every sign either bakes a field or is refused with an Error, as the registries say.
TEST(Registries, EveryMethodAndSignEitherBakesOrIsRefused) {
    const Mesh mesh = icosphere(1.0f, 1);
    const Bvh tree(mesh);
    for (const Choice<DistanceMethod>& method : distanceMethodChoices()) {
        for (const Choice<SignMethod>& sign : signMethodChoices()) {
            BakeSettings settings;
            settings.res = 6;
            settings.rays = 8;
            settings.method = method.id;
            settings.sign = sign.id;
            settings.device = "cpu";
            const DistanceMethodPlugin& plugin = distanceMethod(method.id);
            const bool refused = plugin.fixedSign && sign.id != SignMethod::Default && sign.id != SignMethod::Auto && sign.id != plugin.defaultSign;
            try {
                const BakeResult result = bake(mesh, tree, settings, {});
                EXPECT_FALSE(refused) << method.name << " " << sign.name;
                EXPECT_EQ(result.field.dense().method, method.name);
                EXPECT_LT(result.field.dense().values[result.field.dense().grid.index(3, 3, 3)], 0.0f) << method.name << " " << sign.name;
            } catch (const Error& e) {
                EXPECT_TRUE(refused) << method.name << " " << sign.name << ": " << e.what();
            }
        }
    }
}

struct Decided {
    SignDecision decision;
    bool readTopology = false, ranCheck = false;
};

Decided decide(const Mesh& mesh, SignMethod asked, SignMethod whenDefault) {
    const Bvh tree(mesh);
    const MeshTopology topology(mesh, tree);
    const MeshCheck check = topology.check(mesh, tree);
    Decided d;
    d.decision = decideSign(
        asked, whenDefault,
        [&]() -> const MeshTopology& {
            d.readTopology = true;
            return topology;
        },
        [&]() -> const MeshCheck& {
            d.ranCheck = true;
            return check;
        });
    return d;
}

TEST(DecideSign, AutoTakesThePseudonormalOnlyWhereTheCheckProvesItRight) {
    const Decided closed = decide(icosphere(1.0f, 2), SignMethod::Auto, SignMethod::Auto);
    EXPECT_EQ(closed.decision.sign, SignMethod::Pseudonormal);
    EXPECT_TRUE(closed.decision.checked && closed.ranCheck);
    EXPECT_FALSE(closed.decision.flipped);
    EXPECT_CONTAINS(closed.decision.reason, "pseudonormal: the mesh is closed");

    // Holes decide already from the edges: no search for self-intersections.
    const Decided open = decide(holedSphere(1.0f), SignMethod::Default, SignMethod::Auto);
    EXPECT_EQ(open.decision.sign, SignMethod::Winding);
    EXPECT_FALSE(open.ranCheck);
    EXPECT_EQ(open.decision.reason, "winding: the mesh has holes");

    const Mesh insideOut = translated(icosphere(1.0f, 2), glm::vec3(0.0f), true);
    const Decided flipped = decide(insideOut, SignMethod::Auto, SignMethod::Auto);
    EXPECT_EQ(flipped.decision.sign, SignMethod::Pseudonormal);
    EXPECT_TRUE(flipped.decision.flipped);
    EXPECT_CONTAINS(flipped.decision.reason, "the mesh is inside out");
    EXPECT_TRUE(flipped.decision.warnings.empty());

    // Every sign auto may settle to is among those estimated before it runs.
    for (const Decided* d : {&closed, &open}) {
        const std::vector<SignMethod> possible = possibleSigns(SignMethod::Auto, SignMethod::Auto);
        EXPECT_NE(std::find(possible.begin(), possible.end(), d->decision.sign), possible.end());
    }
}

TEST(DecideSign, ANamedSignIsKeptAndWarnedOfWhereTheMeshDefeatsIt) {
    const Decided rays = decide(icosphere(1.0f, 1), SignMethod::Default, SignMethod::Rays);
    EXPECT_EQ(rays.decision.sign, SignMethod::Rays);
    EXPECT_FALSE(rays.decision.checked || rays.readTopology || rays.ranCheck);
    EXPECT_TRUE(rays.decision.reason.empty() && rays.decision.warnings.empty());

    const Mesh insideOut = translated(icosphere(1.0f, 2), glm::vec3(0.0f), true);
    const Decided pseudonormal = decide(insideOut, SignMethod::Pseudonormal, SignMethod::Auto);
    EXPECT_EQ(pseudonormal.decision.sign, SignMethod::Pseudonormal);
    EXPECT_FALSE(pseudonormal.decision.flipped || pseudonormal.ranCheck);
    ASSERT_EQ(pseudonormal.decision.warnings.size(), 1u);
    EXPECT_CONTAINS(pseudonormal.decision.warnings[0], "sign pseudonormal follows the faces");
}

} // namespace
} // namespace sdfgen
