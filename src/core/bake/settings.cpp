// problem(): the one check of BakeSettings that bake() and every front end share.
#include "core/method/methods.hpp"
#include "sdfgen/bake.hpp"
#include "sdfgen/error.hpp"

#include <cstdio>
#include <optional>
#include <string>
#include <utility>

namespace sdfgen {

namespace {
// Enough digits that a value just past a limit does not read as the limit (1000000001, not 1e+09).
std::string number(double value) {
    char text[32];
    std::snprintf(text, sizeof(text), "%.15g", value);
    return text;
}
} // namespace

std::optional<SettingsProblem> problem(const BakeSettings& settings) {
    auto refuse = [](const char* setting, std::string message) { return SettingsProblem{setting, std::move(message)}; };
    if (settings.res < 1 || settings.res > kMaxRes) {
        return refuse("res", "res must be from 1 to " + std::to_string(kMaxRes) + " voxels along the longest side (got " +
                                 std::to_string(settings.res) + ")");
    }
    if (!(settings.padding >= 0.0 && settings.padding <= kMaxPadding)) {
        return refuse("padding",
                      "padding must be a finite number from 0 to " + number(kMaxPadding) + " (got " + number(settings.padding) + ")");
    }
    if (settings.rays < 1 || settings.rays > kMaxRays) {
        return refuse("rays", "rays must be from 1 to " + std::to_string(kMaxRays) + " per sample (got " + std::to_string(settings.rays) + ")");
    }
    const bool banded = settings.band != 0;
    if (banded && !(settings.band >= 1.0 && settings.band <= kMaxBand)) {
        return refuse("band", "band must be 0 (a dense field) or a finite number of voxels from 1 to " + number(kMaxBand) + " (got " +
                                  number(settings.band) + ")");
    }

    const DistanceMethodPlugin& method = distanceMethod(settings.method);
    const SignMethod sign = settings.sign == SignMethod::Default ? method.defaultSign : settings.sign;
    if (method.fixedSign && sign != SignMethod::Auto && sign != method.defaultSign) {
        return refuse("sign",
                      std::string("method ") + method.name + " signs by the exact winding number; sign " + toString(sign) + " does not apply");
    }
    // A compute device (sdfgen/device.hpp) measures exact distances and counts winding numbers.
    std::string device;
    try {
        device = parseDevice(settings.device);
    } catch (const Error& e) {
        return refuse("device", e.what());
    }
    const bool namedDevice = device != "cpu" && device != "auto";
    if (namedDevice && !method.onDevice) {
        return refuse("device", "device " + device + " computes exact distances; method " + method.name + " runs on the CPU");
    }
    if (banded) {
        if (!method.bricks) {
            return refuse("method", std::string("a band bake measures exact distances; method ") + method.name + " makes dense fields only");
        }
        if (namedDevice) return refuse("device", "a band bake runs on the CPU only; choose device cpu or auto");
        if (settings.channels.any()) {
            return refuse("channels", "channels " + toString(settings.channels).substr(4) +
                                          " come from the dense bake only; a band bake gives the distance (sdf)");
        }
        if (signMethod(sign).band == BandSigning::Never) {
            return refuse("sign", std::string("a band bake signs by the winding number (or auto); sign ") + signMethod(sign).name +
                                      " decides per sample, and most samples of a band are never measured");
        }
    }
    if (settings.channels.any()) {
        const std::string named = toString(settings.channels).substr(4); // without "sdf,"
        if (!method.makesChannels) {
            return refuse("channels", "channels " + named + " come from the exact method's nearest triangles; method " + method.name +
                                          " gives the distance (sdf) only");
        }
        if (namedDevice) return refuse("device", "channels " + named + " are made on the CPU only; choose device cpu or auto");
    }
    return std::nullopt;
}

} // namespace sdfgen
