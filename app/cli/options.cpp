#include "options.h"

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "fray/core/normalize.h"

namespace fray::cli {

void addImportFlags(CLI::App* cmd, ImportFlags& flags) {
    cmd->add_option("--units", flags.units, "Source length unit: m, cm, mm, inch, cmu, or metres per unit (default: detect)");
    cmd->add_option("--up", flags.up, "Source up axis: y or z (default: detect)");
    cmd->add_option("--animation", flags.animation, "Animation to import from multi-animation files (default: first)");
    cmd->add_flag("--raw", flags.raw, "Keep file units and axes (no normalisation)");
}

void addPostureFlag(CLI::App* cmd, std::string& mode, const std::string& help) {
    cmd->add_option("--posture", mode, help);
}

Result<posture::Mode> postureMode(const std::string& flag) {
    const auto mode = posture::parseMode(flag.empty() ? "kinematic" : flag);
    if (!mode) return makeError("--posture: '" + flag + "' is not kinematic or physics");
    return *mode;
}

void addHandPinsFlag(CLI::App* cmd, bool& on) {
    cmd->add_flag("--hand-pins", on,
                  "With --posture physics: pin a porter's hands to the luggage it holds (hard constraints; off by default, "
                  "docs/POSTURE.md)");
}

Result<posture::Options> postureOptions(const std::string& mode, bool handPins) {
    posture::Options o;
    if (handPins && mode != "physics") return makeError("--hand-pins: only with --posture physics");
    o.handPins = handPins;
    return o;
}

void printPostureNotes(const posture::Report& r, bool quiet) {
    if (quiet) return;
    if (r.refusedPins + r.releasedPins + r.nonFiniteTargets + r.resets + r.initialOverlaps > 0) {
        std::fprintf(stderr,
                     "posture: %d foot pins refused, %d let go, %d non-finite targets held, %d resets, %d pairs starting inside each other\n",
                     r.refusedPins, r.releasedPins, r.nonFiniteTargets, r.resets, r.initialOverlaps);
    }
    for (const auto& n : r.notes) std::fprintf(stderr, "note: %s\n", n.c_str());
}

namespace {

CLI::Validator numberCheck(double lo, double hi, bool openLow) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%c%g, %g]", openLow ? '(' : '[', lo, hi);
    const std::string range = buf;
    return CLI::Validator(
        [lo, hi, openLow, range](std::string& text) -> std::string {
            double v = 0;
            const char* end = text.data() + text.size();
            const auto [p, ec] = std::from_chars(text.data(), end, v);
            if (ec != std::errc() || p != end || !std::isfinite(v) || v < lo || v > hi || (openLow && v == lo)) {
                return text + " must be a finite number in " + range;
            }
            return {};
        },
        "NUMBER in " + range);
}

}  // namespace

CLI::Validator finiteRange(double lo, double hi) { return numberCheck(lo, hi, false); }
CLI::Validator finitePositive(double hi) { return numberCheck(0.0, hi, true); }

Result<LoadOptions> toLoadOptions(const ImportFlags& flags) {
    LoadOptions o;
    o.animation = flags.animation;
    o.doNormalize = !flags.raw;
    if (!flags.units.empty()) {
        const std::string& u = flags.units;
        if (auto named = unitScaleByName(u)) o.normalize.unitScale = *named;
        else {
            double v = 0;
            auto [p, ec] = std::from_chars(u.data(), u.data() + u.size(), v);
            if (ec != std::errc() || p != u.data() + u.size() || !(v > 0) || !std::isfinite(v) || v > 1e6)
                return makeError("--units: expected m, cm, mm, inch, cmu or a positive number, got '" + u + "'");
            o.normalize.unitScale = v;
        }
    }
    if (!flags.up.empty()) {
        o.normalize.upAxis = upAxisByName(flags.up);
        if (!o.normalize.upAxis) return makeError("--up: expected y or z, got '" + flags.up + "'");
    }
    return o;
}

}  // namespace fray::cli
