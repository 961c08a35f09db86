// problem(): the one check of BakeSettings that bake() and every front end share (the command line
// and Python against each other: tests/python/test_settings.py).
#include "sdfgen/bake.hpp"
#include "support/checks.hpp"
#include "support/shapes.hpp"
#include "support/stand_in_device.hpp"

#include <gtest/gtest.h>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

namespace sdfgen {
namespace {

// The setting problem() names for `settings`, "" when it finds none.
std::string refusedSetting(const BakeSettings& settings) {
    const std::optional<SettingsProblem> refused = problem(settings);
    return refused ? refused->setting : "";
}

TEST(Settings, EachLimitIsRefusedJustPastItAndNamesItsSetting) {
    EXPECT_EQ(refusedSetting(BakeSettings{}), "");
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    struct Limit {
        const char* setting;
        void (*set)(BakeSettings&, double);
        std::vector<double> accepted, refused;
    };
    const Limit limits[] = {
        {"res", [](BakeSettings& s, double v) { s.res = int(v); }, {1, kMaxRes}, {0, -1, kMaxRes + 1}},
        {"padding", [](BakeSettings& s, double v) { s.padding = v; }, {0, 0.1, kMaxPadding}, {-1e-9, kMaxPadding * 1.000001, nan, inf, -inf}},
        {"rays", [](BakeSettings& s, double v) { s.rays = int(v); }, {1, kMaxRays}, {0, -1, kMaxRays + 1, 1e8}},
        {"band", [](BakeSettings& s, double v) { s.band = v; }, {0, 1, 2.5, kMaxBand}, {0.5, -1, nan, inf, kMaxBand * 1.000001}},
    };
    for (const Limit& limit : limits) {
        for (double value : limit.accepted) {
            BakeSettings settings;
            limit.set(settings, value);
            EXPECT_EQ(refusedSetting(settings), "") << limit.setting << " " << value;
        }
        for (double value : limit.refused) {
            BakeSettings settings;
            limit.set(settings, value);
            EXPECT_EQ(refusedSetting(settings), limit.setting) << limit.setting << " " << value;
        }
    }
}

TEST(Settings, CombinationsAreRefusedByTheSettingToChange) {
    const test::ScopedDevice standIn(test::standInDevice("stand-in", true));
    BakeSettings s;
    s.method = DistanceMethod::Brute;
    s.sign = SignMethod::Rays;
    EXPECT_EQ(refusedSetting(s), "sign");
    EXPECT_EQ(problem(s)->message, "method brute signs by the exact winding number; sign rays does not apply");
    s = {};
    s.method = DistanceMethod::Rays;
    s.device = "stand-in";
    EXPECT_EQ(refusedSetting(s), "device");
    s.device = "cpu";
    s.band = 2;
    EXPECT_EQ(refusedSetting(s), "method");
    s = {};
    s.band = 2;
    s.device = "stand-in";
    EXPECT_EQ(refusedSetting(s), "device");
    s.device = "auto";
    s.sign = SignMethod::Rays;
    EXPECT_EQ(refusedSetting(s), "sign");
    s.sign = SignMethod::Default;
    s.channels.add("gradient");
    EXPECT_EQ(refusedSetting(s), "channels");
    s.band = 0;
    EXPECT_EQ(refusedSetting(s), "");
    s.method = DistanceMethod::Rays;
    EXPECT_EQ(refusedSetting(s), "channels");
    s.method = DistanceMethod::Exact;
    s.device = "stand-in";
    EXPECT_EQ(refusedSetting(s), "device");
    s = {};
    s.device = "tpu";
    EXPECT_EQ(refusedSetting(s), "device");
    EXPECT_EQ(problem(s)->message.rfind("unknown device 'tpu'; known: cpu (the CPU), stand-in (", 0), 0u) << problem(s)->message;
}

TEST(Settings, MessagesNameSettingsNotCommandLineOptions) {
    const test::ScopedDevice standIn(test::standInDevice("stand-in", true));
    BakeSettings s;
    s.res = 0;
    EXPECT_EQ(problem(s)->message, "res must be from 1 to 65536 voxels along the longest side (got 0)");
    s = {};
    s.rays = 100000000;
    EXPECT_EQ(problem(s)->message, "rays must be from 1 to 65536 per sample (got 100000000)");
    for (DistanceMethod method : {DistanceMethod::Exact, DistanceMethod::Rays, DistanceMethod::Brute}) {
        for (SignMethod sign : {SignMethod::Default, SignMethod::Auto, SignMethod::Rays, SignMethod::Pseudonormal, SignMethod::Winding}) {
            for (const Choice<std::string>& device : deviceChoices()) {
                for (double band : {0.0, 2.0}) {
                    for (const Channels& channels : {Channels{}, Channels::all()}) {
                        s = {};
                        s.method = method, s.sign = sign, s.device = device.id, s.band = band, s.channels = channels;
                        if (const std::optional<SettingsProblem> refused = problem(s)) {
                            EXPECT_EQ(refused->message.find("--"), std::string::npos) << refused->message;
                        }
                    }
                }
            }
        }
    }
}

// Whatever problem() lets through bakes (on a closed box, where every sign is proven right), and
// whatever it refuses the bake refuses with its message: the front ends' check is the bake's own.
TEST(Settings, TheBakeRefusesExactlyWhatProblemRefuses) {
    const Mesh box = test::box({1, 1, 1});
    for (DistanceMethod method : {DistanceMethod::Exact, DistanceMethod::Rays, DistanceMethod::Brute}) {
        for (SignMethod sign : {SignMethod::Default, SignMethod::Auto, SignMethod::Rays, SignMethod::Pseudonormal, SignMethod::Winding}) {
            for (double band : {0.0, 1.0}) {
                for (const Channels& channels : {Channels{}, Channels::all()}) {
                    BakeSettings s;
                    s.res = 6, s.rays = 4, s.device = "cpu";
                    s.method = method, s.sign = sign, s.band = band, s.channels = channels;
                    const std::optional<SettingsProblem> refused = problem(s);
                    if (refused) {
                        EXPECT_EQ(test::errorFrom([&] { test::bakeMesh(box, s, 1); }), refused->message);
                    } else {
                        EXPECT_NO_THROW(test::bakeMesh(box, s, 1)) << toString(method) << " " << toString(sign) << " band " << band;
                    }
                }
            }
        }
    }
    BakeSettings s;
    s.rays = 100000000;
    EXPECT_EQ(test::errorFrom([&] { test::bakeMesh(box, s, 1); }), problem(s)->message);
}

} // namespace
} // namespace sdfgen
