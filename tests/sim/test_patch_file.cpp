// The patch library file (docs/PATCHES.md, "Library file"): it stores the
// connection tables so a loaded library is complete and composes exactly what
// the freshly generated one does; any damage is refused; tables made under
// another link rule are rebuilt or refused, never used; the same project makes
// the same bytes. Also the typed errors of fray/core/result.h. A small library
// (coarse grid, four variants per entry) keeps it quick under the sanitizers.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <string>

#include "fray/core/atomic_file.h"
#include "fray/core/progress.h"
#include "fray/core/result.h"
#include "fray/sim/compose.h"
#include "fray/sim/compose/domino.h"
#include "fray/sim/compose/one_vs_many.h"
#include "fray/sim/compose/one_vs_one.h"
#include "fray/sim/patches.h"
#include "fray/sim/patterns.h"
#include "sim/demo_world.h"
#include "temp_dir.h"

namespace fray::sim {
namespace {

using test::demoWorld;

constexpr std::size_t kRuleAt = 12;  // magic (8), file version (4)

PatternList pattern(const std::string& name) {
    for (const auto& p : defaultPatterns()) {
        if (p.name == name) return p;
    }
    throw std::runtime_error("no pattern " + name);
}

// A small library, generated from scratch (no tables).
PatchLibrary generateSmall(std::initializer_list<const char*> names) {
    GenerateOptions opt;
    opt.maxChoicesPerEntry = 4;
    opt.distanceStep = 0.4;
    opt.angleStepDegrees = 45;
    opt.delayStep = 0.2;
    PatchLibrary out;
    for (const char* name : names) {
        if (auto st = generatePatches(demoWorld().library, pattern(name), PatternSet{}, out, opt); !st) {
            throw std::runtime_error(st.error().message);
        }
    }
    return out;
}

// Fights and falls with their tables (made once).
const PatchLibrary& smallLibrary() {
    static const PatchLibrary lib = [] {
        PatchLibrary out = generateSmall({"attack-fall", "attack-defence-attack-fall", "fall-fall"});
        buildConnections(demoWorld().library, out);
        return out;
    }();
    return lib;
}

std::string bytesOf(const PatchLibrary& lib) {
    auto bytes = patchLibraryBytes(lib);
    if (!bytes) throw std::runtime_error(bytes.error().message);
    return *bytes;
}

// Recomputes the trailing CRC-32 after an edit (a file that is consistent but says something else).
void reseal(std::string& bytes) {
    const std::uint32_t crc = patchFileChecksum(std::string_view(bytes).substr(0, bytes.size() - 4));
    std::memcpy(bytes.data() + bytes.size() - 4, &crc, sizeof crc);
}

void expectSameTables(const PatchLibrary& a, const PatchLibrary& b) {
    ASSERT_TRUE(a.complete());
    ASSERT_TRUE(b.complete());
    ASSERT_EQ(a.temporal().size(), b.temporal().size());
    std::size_t links = 0;
    for (std::size_t i = 0; i < a.temporal().size(); ++i) {
        ASSERT_EQ(a.temporal()[i].size(), b.temporal()[i].size()) << "patch " << i;
        for (std::size_t k = 0; k < a.temporal()[i].size(); ++k) {
            const auto &x = a.temporal()[i][k], &y = b.temporal()[i][k];
            ASSERT_TRUE(x.to == y.to && x.roles == y.roles && x.shared == y.shared) << "patch " << i << " link " << k;
        }
        ASSERT_EQ(a.spatial()[i].size(), b.spatial()[i].size()) << "patch " << i;
        for (std::size_t k = 0; k < a.spatial()[i].size(); ++k) {
            const auto &x = a.spatial()[i][k], &y = b.spatial()[i][k];
            ASSERT_TRUE(x.to == y.to && x.sharedA == y.sharedA && x.sharedB == y.sharedB && x.offset == y.offset && x.from == y.from)
                << "patch " << i << " spatial link " << k;
        }
        links += a.temporal()[i].size() + a.spatial()[i].size();
    }
    EXPECT_GT(links, 0u);
    EXPECT_EQ(a.standardPoses(), b.standardPoses());
    EXPECT_EQ(a.initialPose(), b.initialPose());
    EXPECT_EQ(a.finalPose(), b.finalPose());
}

// Scenes that use temporal links, standard poses and spatial links.
std::vector<ComposeSpec> specs() {
    std::vector<ComposeSpec> out(3);
    out[0] = ComposeSpec::of(OneVsManySpec{.enemies = 3}), out[0].duration = 40;
    out[1] = ComposeSpec::of(OneVsOneSpec{}), out[1].duration = 15;
    FloorBitmap floor;
    floor.width = floor.height = 80;
    floor.metresPerPixel = 0.1;
    floor.origin = glm::vec2(-4.0f);
    floor.painted.assign(80 * 80, 1);
    DominoSpec domino;
    domino.floor = floor, domino.starts = {{0.2, glm::vec2(0.0f)}}, domino.background = 4;
    out[2] = ComposeSpec::of(domino);
    return out;
}

TEST(PatchFile, LoadedLibraryIsCompleteAndComposesTheSameScenes) {
    const auto& lib = demoWorld().library;
    const auto& fresh = smallLibrary();
    ASSERT_GE(fresh.patches().size(), 40u);
    const test::TempDir dir("fray_patch_file_");
    ASSERT_TRUE(savePatchLibrary(fresh, dir / "s.patches"));
    auto loaded = loadPatchLibrary(dir / "s.patches", lib);
    ASSERT_TRUE(loaded) << loaded.error().message;
    EXPECT_TRUE(loaded->complete());  // no buildConnections
    expectSameTables(*loaded, fresh);
    int composed = 0;
    for (const auto& spec : specs()) {
        auto a = compose(lib, fresh, spec);
        auto b = compose(lib, *loaded, spec);
        ASSERT_EQ(a.ok(), b.ok()) << spec.kind << ": " << (a ? b.error().message : a.error().message);
        if (!a) continue;
        ++composed;
        EXPECT_EQ(sceneToJson(*a, lib), sceneToJson(*b, lib)) << spec.kind;
    }
    EXPECT_GE(composed, 2);
    // What loads saves to the same bytes.
    EXPECT_EQ(bytesOf(*loaded), *readWholeFile(dir / "s.patches"));
}

TEST(PatchFile, GenerationIsByteReproducible) {
    const auto& lib = demoWorld().library;
    std::string bytes[2];
    for (auto& b : bytes) {
        PatchLibrary out = generateSmall({"attack-fall", "fall-fall"});
        buildConnections(lib, out);
        b = bytesOf(out);
    }
    EXPECT_GT(bytes[0].size(), 10000u);
    EXPECT_EQ(bytes[0].size(), bytes[1].size());
    EXPECT_TRUE(bytes[0] == bytes[1]) << "two generations of the same project differ";
}

TEST(PatchFile, SavingAnIncompleteLibraryIsRefused) {
    PatchLibrary out = generateSmall({"attack-fall"});
    ASSERT_FALSE(out.complete());
    const test::TempDir dir("fray_patch_file_");
    const Status st = savePatchLibrary(out, dir / "x.patches");
    ASSERT_FALSE(st);
    EXPECT_TRUE(st.error().is(ErrorKind::Internal));
    EXPECT_NE(st.error().message.find("x.patches"), std::string::npos) << st.error().message;
    EXPECT_FALSE(std::filesystem::exists(dir / "x.patches"));
}

// A one-bit flip anywhere (header, patches, tables, checksum) is refused,
// naming the file; so are a truncated file and bytes appended to one.
TEST(PatchFile, DamagedFileIsRefused) {
    const auto& lib = demoWorld().library;
    const std::string good = bytesOf(smallLibrary());
    ASSERT_TRUE(readPatchLibrary(good, "good.patches", lib));
    const std::size_t probes = 400;
    std::size_t accepted = 0;
    for (std::size_t k = 0; k < probes; ++k) {
        // Every header and trailer byte, then positions spread over the rest.
        const std::size_t at = k < 32 ? k : k < 40 ? good.size() - (k - 31) : 32 + (k * 7919) % (good.size() - 40);
        std::string bad = good;
        bad[at] = static_cast<char>(bad[at] ^ (1 << (k % 8)));
        auto r = readPatchLibrary(bad, "damaged.patches", lib);
        if (r) {
            ++accepted;
            ADD_FAILURE() << "a flip at byte " << at << " of " << good.size() << " was accepted";
            continue;
        }
        EXPECT_EQ(r.error().message.rfind("damaged.patches: ", 0), 0u) << r.error().message;
    }
    EXPECT_EQ(accepted, 0u);
    for (const std::string& bad : {good.substr(0, good.size() - 1), good.substr(0, good.size() / 2), good + std::string(1, '\0')}) {
        auto r = readPatchLibrary(bad, "cut.patches", lib);
        ASSERT_FALSE(r);
        EXPECT_NE(r.error().message.find("cut.patches: the patch library is truncated or corrupt"), std::string::npos)
            << r.error().message;
    }
}

TEST(PatchFile, OlderVersionAndOtherActionsAreRefused) {
    const auto& lib = demoWorld().library;
    std::string old = bytesOf(smallLibrary());
    const std::uint32_t three = 3;
    std::memcpy(old.data() + 8, &three, sizeof three);
    auto r = readPatchLibrary(old, "old.patches", lib);
    ASSERT_FALSE(r);
    EXPECT_TRUE(r.error().is(ErrorKind::Unsupported));
    EXPECT_NE(r.error().message.find("old.patches: patch library version 3"), std::string::npos) << r.error().message;
    EXPECT_NE(r.error().message.find("generate the patches again"), std::string::npos);
    std::vector<LibraryAction> changed = lib.actions();
    changed[0].lastFrame += 1;  // one action cut differently
    const ActionLibrary recut = ActionLibrary::catalogue(changed, lib.vocabulary());
    r = readPatchLibrary(bytesOf(smallLibrary()), "recut.patches", recut);
    ASSERT_FALSE(r);
    EXPECT_TRUE(r.error().is(ErrorKind::Stale));
    EXPECT_NE(r.error().message.find("recut.patches: made from other actions"), std::string::npos) << r.error().message;
}

// Tables stored under another link rule: refused, or rebuilt (with a notice
// naming the file) from the patches; what they held is never used.
TEST(PatchFile, StaleLinkRuleIsRebuiltOrRefused) {
    const auto& lib = demoWorld().library;
    const auto& fresh = smallLibrary();
    std::string stale = bytesOf(fresh);
    const std::uint32_t other = kPatchLinkRule + 1;
    std::memcpy(stale.data() + kRuleAt, &other, sizeof other);
    // Wrong tables too: every dense temporal row and spatial link count
    // would mislead a reader that trusted them.
    for (std::size_t at = stale.size() - 4 - 64; at < stale.size() - 4; ++at) stale[at] = static_cast<char>(0xff);
    reseal(stale);

    PatchFileOptions refuse;
    refuse.staleTables = StaleTables::Refuse;
    auto r = readPatchLibrary(stale, "stale.patches", lib, refuse);
    ASSERT_FALSE(r);
    EXPECT_TRUE(r.error().is(ErrorKind::Stale));
    EXPECT_NE(r.error().message.find("stale.patches: its connection tables follow link rule " + std::to_string(other)),
              std::string::npos)
        << r.error().message;

    std::string notice;
    PatchFileOptions rebuild;
    rebuild.notice = [&](const std::string& n) { notice = n; };
    r = readPatchLibrary(stale, "stale.patches", lib, rebuild);
    ASSERT_TRUE(r) << r.error().message;
    EXPECT_NE(notice.find("stale.patches"), std::string::npos) << notice;
    EXPECT_NE(notice.find("rebuilt"), std::string::npos) << notice;
    expectSameTables(*r, fresh);

    // Rebuilding is cancelled through the progress callback like any long step.
    const std::atomic<bool> stop{true};
    PatchFileOptions cancelling;
    cancelling.progress = cancelWhen(stop);
    r = readPatchLibrary(stale, "stale.patches", lib, cancelling);
    ASSERT_FALSE(r);
    EXPECT_TRUE(r.error().isCancelled()) << r.error().message;
}

TEST(ErrorKinds, DefaultKindHelpersAndNames) {
    EXPECT_TRUE(makeError("x.json:3: bad").is(ErrorKind::InvalidInput));
    EXPECT_TRUE(makeError(ErrorKind::Io, "x: cannot open").is(ErrorKind::Io));
    EXPECT_TRUE(cancelled().isCancelled());
    EXPECT_EQ(cancelled().message, "cancelled");
    EXPECT_EQ(cancelled("motion graph").message, "motion graph: cancelled");
    EXPECT_FALSE(makeError("cancelled").isCancelled());  // the kind, not the words
    EXPECT_STREQ(errorKindName(ErrorKind::Stale), "stale");
    // A flag cancels through the progress callback, which still reports.
    std::atomic<bool> flag{false};
    int reports = 0;
    const ProgressFn p = cancelWhen(flag, [&](double, std::string_view) { return ++reports > 0; });
    EXPECT_TRUE(reportProgress(p, 0.5, "x"));
    flag = true;
    EXPECT_FALSE(reportProgress(p, 0.6, "x"));
    EXPECT_EQ(reports, 1);
}

}  // namespace
}  // namespace fray::sim
