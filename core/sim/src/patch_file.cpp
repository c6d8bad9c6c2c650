// The patch library file (docs/PATCHES.md, "Library file"): the patches, their
// connection tables and standard poses, sealed by a CRC-32. Little-endian
// fixed-size fields and LEB128 counts, bounds-checked on read.
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "fray/core/atomic_file.h"
#include "fray/core/byte_io.h"
#include "fray/sim/patches.h"
#include "patch_library_builder.h"

namespace fray::sim {

namespace {

constexpr char kMagic[8] = {'F', 'R', 'A', 'Y', 'P', 'T', 'C', 'H'};
constexpr std::size_t kHeader = sizeof(kMagic) + 4 + 4 + 8;  // magic, file version, link rule, library key
constexpr std::size_t kTrailer = 4;                          // CRC-32
constexpr std::size_t kMaxPoses = 1024;

// Temporal links of one (a, b) pair: 2 bits per role mapping (0: no link;
// 1, 2, 3: a link whose `shared` is -1, 0, 1).
std::uint8_t pairState(const std::vector<TemporalLink>& row, std::size_t& at, int to) {
    std::uint8_t state = 0;
    while (at < row.size() && row[at].to == to) {
        state |= static_cast<std::uint8_t>((row[at].shared + 2) << (2 * row[at].roles));
        ++at;
    }
    return state;
}

// The file's own records on top of the byte writer and reader (fray/core/byte_io.h).
struct Writer : ByteWriter {
    void xf(const RootXf& r) { put(r.pos.x), put(r.pos.y), put(r.heading); }
    void cfg(const PatchConfig& c) { put(c.r), put(c.theta1), put(c.theta2), put(c.delay); }
};

std::size_t varSize(std::uint64_t v) {
    std::size_t n = 1;
    while (v >= 0x80) v >>= 7, ++n;
    return n;
}

struct Reader : ByteReader {
    RootXf xf() {
        RootXf r;
        r.pos.x = get<float>(), r.pos.y = get<float>(), r.heading = get<double>();
        return r;
    }
    PatchConfig cfg() {
        PatchConfig c;
        c.r = get<double>(), c.theta1 = get<double>(), c.theta2 = get<double>(), c.delay = get<double>();
        return c;
    }
};

void writePatterns(Writer& w, const PatchLibrary& lib) {
    w.put(static_cast<std::uint32_t>(lib.patterns().size()));
    for (const auto& p : lib.patterns()) {
        w.str(p.name);
        w.put(static_cast<std::uint32_t>(p.entries.size()));
        for (const auto& e : p.entries) w.put(static_cast<std::int32_t>(e.character)), w.str(e.annotation);
        w.put(p.weights.contact), w.put(p.weights.distance), w.put(p.weights.timing), w.put(p.threshold);
        w.put(static_cast<std::int32_t>(p.keepPerPath));
        w.put(static_cast<std::uint8_t>(p.spread ? 1 : 0));
    }
}

void writePatches(Writer& w, const PatchLibrary& lib) {
    w.put(static_cast<std::uint32_t>(lib.patches().size()));
    for (const auto& p : lib.patches()) {
        w.put(static_cast<std::int32_t>(p.pattern));
        w.put(p.duration), w.put(p.score), w.put(p.contact), w.put(p.distance), w.put(p.timing);
        w.cfg(p.initial), w.cfg(p.final);
        w.put(static_cast<std::uint8_t>(p.handMade));
        for (const auto& t : p.tracks) {
            w.put(static_cast<std::uint32_t>(t.size()));
            for (const auto& i : t) {
                w.put(static_cast<std::int32_t>(i.action)), w.put(i.start), w.put(i.offset), w.put(i.end);
                w.xf(i.root);
                w.put(static_cast<std::uint8_t>((i.forced ? 1 : 0) | (i.fallback ? 2 : 0)));
            }
        }
        w.put(static_cast<std::uint32_t>(p.hits.size()));
        for (const auto& h : p.hits) {
            w.put(h.time), w.put(static_cast<std::int32_t>(h.attacker)), w.put(static_cast<std::int32_t>(h.defender));
            w.put(static_cast<std::int32_t>(h.attackAction)), w.put(static_cast<std::int32_t>(h.effector));
            w.put(static_cast<std::int32_t>(h.target)), w.put(h.speed), w.put(h.impulse), w.put(static_cast<std::uint8_t>(h.blocked));
        }
        for (const auto& s : p.swept) {
            w.put(static_cast<std::uint32_t>(s.size()));
            for (const auto& b : s) w.put(b.lo.x), w.put(b.lo.y), w.put(b.hi.x), w.put(b.hi.y);
        }
    }
    // The counters, not the wall-clock time: the same project makes the same bytes.
    GenerateStats::zipCounts(lib.stats(), lib.stats(), [&](const auto& v, const auto&) { w.put(v); });
}

// Standard poses, then per patch its poses, temporal row and spatial row.
void writeTables(Writer& w, const PatchLibrary& lib) {
    w.var(lib.standardPoses().size());
    for (const auto& c : lib.standardPoses()) w.cfg(c);
    const auto n = lib.patches().size();
    for (std::size_t i = 0; i < n; ++i) w.var(static_cast<std::uint64_t>(lib.initialPose()[i])), w.var(static_cast<std::uint64_t>(lib.finalPose()[i]));
    std::vector<std::uint8_t> states(n);
    for (std::size_t i = 0; i < n; ++i) {
        // Per target patch, the state of its pair; then whichever of a dense
        // row (a nibble per patch) or a sparse one (gap and state per linked
        // patch) is shorter.
        const auto& row = lib.temporal()[i];
        std::size_t at = 0, linked = 0, sparseBytes = 0;
        int last = -1;
        for (std::size_t b = 0; b < n; ++b) {
            states[b] = pairState(row, at, static_cast<int>(b));
            if (states[b] == 0) continue;
            ++linked;
            sparseBytes += varSize(static_cast<std::uint64_t>(static_cast<int>(b) - last - 1)) + 1;
            last = static_cast<int>(b);
        }
        sparseBytes += varSize(linked);
        const std::size_t denseBytes = (n + 1) / 2;
        if (sparseBytes < denseBytes) {
            w.put(std::uint8_t{0});
            w.var(linked);
            last = -1;
            for (std::size_t b = 0; b < n; ++b) {
                if (states[b] == 0) continue;
                w.var(static_cast<std::uint64_t>(static_cast<int>(b) - last - 1));
                w.put(states[b]);
                last = static_cast<int>(b);
            }
        } else {
            w.put(std::uint8_t{1});
            for (std::size_t b = 0; b < n; b += 2) {
                w.put(static_cast<std::uint8_t>(states[b] | (b + 1 < n ? states[b + 1] << 4 : 0)));
            }
        }
        w.var(lib.spatial()[i].size());
        for (const auto& l : lib.spatial()[i]) {
            w.var(static_cast<std::uint64_t>(l.to));
            w.put(static_cast<std::uint8_t>(l.sharedA | (l.sharedB << 1)));
            w.put(l.offset), w.put(l.from);
        }
    }
}

// The patterns and patches (and the generation counters) of a file whose header has been read.
void readPatches(Reader& r, int actionCount, PatchLibrary::Data& lib) {
    const std::size_t np = r.count(12);
    for (std::size_t i = 0; i < np && !r.bad; ++i) {
        PatternList p;
        p.name = r.str();
        const std::size_t ne = r.count(8);
        for (std::size_t e = 0; e < ne && !r.bad; ++e) {
            PatternEntry pe;
            pe.character = r.get<std::int32_t>();
            pe.annotation = r.str();
            if (pe.character != 0 && pe.character != 1) r.bad = true;
            p.entries.push_back(pe);
        }
        p.weights.contact = r.get<double>(), p.weights.distance = r.get<double>(), p.weights.timing = r.get<double>();
        p.threshold = r.get<double>();
        p.keepPerPath = r.get<std::int32_t>();
        p.spread = r.get<std::uint8_t>() != 0;
        lib.patterns.push_back(std::move(p));
    }
    const std::size_t nq = r.count(64);
    lib.patches.reserve(nq);
    for (std::size_t i = 0; i < nq && !r.bad; ++i) {
        Patch p;
        p.pattern = r.get<std::int32_t>();
        if (p.pattern < 0 || static_cast<std::size_t>(p.pattern) >= lib.patterns.size()) r.bad = true;
        p.duration = r.get<double>(), p.score = r.get<double>();
        p.contact = r.get<double>(), p.distance = r.get<double>(), p.timing = r.get<double>();
        p.initial = r.cfg(), p.final = r.cfg();
        p.handMade = r.get<std::uint8_t>() != 0;
        for (auto& t : p.tracks) {
            const std::size_t n = r.count(45);  // bytes per action
            if (n == 0) r.bad = true;
            for (std::size_t k = 0; k < n && !r.bad; ++k) {
                ActionInstance inst;
                inst.action = r.get<std::int32_t>();
                inst.start = r.get<double>(), inst.offset = r.get<double>(), inst.end = r.get<double>();
                inst.root = r.xf();
                const auto flags = r.get<std::uint8_t>();
                inst.forced = (flags & 1) != 0, inst.fallback = (flags & 2) != 0;
                if (inst.action < 0 || inst.action >= actionCount || !(inst.end >= inst.start) || flags > 3) r.bad = true;
                t.push_back(inst);
            }
        }
        const std::size_t nh = r.count(45);  // bytes per hit
        for (std::size_t k = 0; k < nh && !r.bad; ++k) {
            HitEvent h;
            h.time = r.get<double>();
            h.attacker = r.get<std::int32_t>(), h.defender = r.get<std::int32_t>();
            h.attackAction = r.get<std::int32_t>(), h.effector = r.get<std::int32_t>(), h.target = r.get<std::int32_t>();
            h.speed = r.get<double>(), h.impulse = r.get<double>();
            h.blocked = r.get<std::uint8_t>() != 0;
            if ((h.attacker != 0 && h.attacker != 1) || (h.defender != 0 && h.defender != 1)) r.bad = true;
            p.hits.push_back(h);
        }
        for (auto& s : p.swept) {
            const std::size_t n = r.count(16);
            if (n == 0) r.bad = true;
            for (std::size_t k = 0; k < n && !r.bad; ++k) {
                SweptBox b;
                b.lo.x = r.get<float>(), b.lo.y = r.get<float>(), b.hi.x = r.get<float>(), b.hi.y = r.get<float>();
                s.push_back(b);
            }
        }
        lib.patches.push_back(std::move(p));
    }
    GenerateStats::zipCounts(lib.stats, lib.stats, [&](auto& v, const auto&) { v = r.get<std::remove_reference_t<decltype(v)>>(); });
}

void readTables(Reader& r, PatchLibrary::Data& lib) {
    const auto n = lib.patches.size();
    const std::size_t poses = r.varCount(32);
    if (poses > kMaxPoses || (n > 0 && poses == 0)) r.bad = true;
    for (std::size_t k = 0; k < poses && !r.bad; ++k) lib.standardPoses.push_back(r.cfg());
    lib.initialPose.assign(n, 0), lib.finalPose.assign(n, 0);
    for (std::size_t i = 0; i < n && !r.bad; ++i) {
        const auto a = r.var(), b = r.var();
        if (a >= poses || b >= poses) r.bad = true;
        lib.initialPose[i] = static_cast<int>(a), lib.finalPose[i] = static_cast<int>(b);
    }
    lib.temporal.assign(n, {}), lib.spatial.assign(n, {});
    auto addPair = [&](std::vector<TemporalLink>& row, std::size_t b, std::uint8_t state) {
        for (int roles = 0; roles < 2; ++roles) {
            const int s = (state >> (2 * roles)) & 3;
            if (s != 0) row.push_back({static_cast<int>(b), static_cast<std::int8_t>(roles), static_cast<std::int8_t>(s - 2)});
        }
    };
    for (std::size_t i = 0; i < n && !r.bad; ++i) {
        auto& row = lib.temporal[i];
        const auto encoding = r.get<std::uint8_t>();
        if (encoding == 0) {
            const std::size_t linked = r.varCount(2);
            if (linked > n) r.bad = true;
            row.reserve(2 * linked);
            std::size_t next = 0;  // the smallest patch the next gap can lead to
            for (std::size_t k = 0; k < linked && !r.bad; ++k) {
                const auto gap = r.var();
                const auto state = r.get<std::uint8_t>();
                if (gap >= n - next || state == 0 || state > 15) {
                    r.bad = true;
                    break;
                }
                const std::size_t b = next + static_cast<std::size_t>(gap);
                addPair(row, b, state);
                next = b + 1;
            }
        } else if (encoding == 1) {
            if (!r.fits((n + 1) / 2, 1)) break;
            const auto* bytes = reinterpret_cast<const std::uint8_t*>(r.in.data() + r.at);
            std::size_t links = 0;
            for (std::size_t k = 0; k < (n + 1) / 2; ++k) {
                const unsigned v = bytes[k];
                links += ((v & 3) != 0) + ((v & 12) != 0) + ((v & 48) != 0) + ((v & 192) != 0);
            }
            if (n % 2 == 1 && (bytes[n / 2] >> 4) != 0) r.bad = true;  // the padding nibble
            row.reserve(links);
            for (std::size_t b = 0; b < n && !r.bad; ++b) {
                const std::uint8_t state = (bytes[b / 2] >> (4 * (b % 2))) & 15;
                if (state != 0) addPair(row, b, state);
            }
            r.at += (n + 1) / 2;
        } else {
            r.bad = true;
        }
        const std::size_t ns = r.varCount(10);
        lib.spatial[i].reserve(ns);
        for (std::size_t k = 0; k < ns && !r.bad; ++k) {
            SpatialLink l;
            const auto to = r.var();
            const auto shared = r.get<std::uint8_t>();
            l.offset = r.get<float>(), l.from = r.get<float>();
            if (to >= n || to == i || shared > 3 || !std::isfinite(l.offset) || !std::isfinite(l.from)) r.bad = true;
            l.to = static_cast<int>(to);
            l.sharedA = static_cast<std::int8_t>(shared & 1), l.sharedB = static_cast<std::int8_t>(shared >> 1);
            lib.spatial[i].push_back(l);
        }
    }
}

// What the writer's encoding assumes of the tables (buildConnections makes
// them so): rows in the order of their targets, one link per role mapping.
bool tablesWellFormed(const PatchLibrary& lib) {
    const auto n = lib.patches().size();
    if (lib.standardPoses().size() > kMaxPoses) return false;
    for (std::size_t i = 0; i < n; ++i) {
        if (lib.initialPose()[i] < 0 || static_cast<std::size_t>(lib.initialPose()[i]) >= lib.standardPoses().size()) return false;
        if (lib.finalPose()[i] < 0 || static_cast<std::size_t>(lib.finalPose()[i]) >= lib.standardPoses().size()) return false;
        long long last = -1;
        for (const auto& l : lib.temporal()[i]) {
            const long long key = 2LL * l.to + l.roles;
            if (l.to < 0 || static_cast<std::size_t>(l.to) >= n || l.roles < 0 || l.roles > 1 || l.shared < -1 || l.shared > 1 ||
                key <= last) {
                return false;
            }
            last = key;
        }
        for (const auto& l : lib.spatial()[i]) {
            if (l.to < 0 || static_cast<std::size_t>(l.to) >= n || static_cast<std::size_t>(l.to) == i || l.sharedA < 0 ||
                l.sharedA > 1 || l.sharedB < 0 || l.sharedB > 1 || !std::isfinite(l.offset) || !std::isfinite(l.from)) {
                return false;
            }
        }
    }
    return true;
}

}  // namespace

bool PatchLibrary::complete() const {
    const auto n = d_.patches.size();
    return d_.temporal.size() == n && d_.spatial.size() == n && d_.initialPose.size() == n && d_.finalPose.size() == n &&
           (n == 0 || !d_.standardPoses.empty());
}

std::uint32_t patchFileChecksum(std::string_view bytes) {
    uLong crc = crc32(0L, Z_NULL, 0);
    // zlib takes lengths as uInt: feed large inputs in pieces.
    while (!bytes.empty()) {
        const std::size_t piece = std::min<std::size_t>(bytes.size(), std::numeric_limits<uInt>::max());
        crc = crc32(crc, reinterpret_cast<const Bytef*>(bytes.data()), static_cast<uInt>(piece));
        bytes.remove_prefix(piece);
    }
    return static_cast<std::uint32_t>(crc);
}

Result<std::string> patchLibraryBytes(const PatchLibrary& lib) {
    if (!lib.complete()) {
        return makeError(ErrorKind::Internal, "the patch library has no connection tables yet (buildConnections before saving it)");
    }
    if (!tablesWellFormed(lib)) return makeError(ErrorKind::Internal, "the patch library's connection tables are malformed");
    Writer w;
    w.out.append(kMagic, sizeof(kMagic));
    w.put(kPatchFileVersion);
    w.put(kPatchLinkRule);
    w.put(lib.libraryKey());
    writePatterns(w, lib);
    writePatches(w, lib);
    writeTables(w, lib);
    w.put(patchFileChecksum(w.out));
    return std::move(w.out);
}

Status savePatchLibrary(const PatchLibrary& lib, const std::filesystem::path& file) {
    auto bytes = patchLibraryBytes(lib);
    if (!bytes) return makeError(bytes.error().kind, file.string() + ": " + bytes.error().message);
    return writeFileAtomically(file, *bytes);
}

Result<PatchLibrary> readPatchLibrary(std::string_view bytes, std::string_view fileName, const ActionLibrary& actions,
                                      const PatchFileOptions& options) {
    const std::string name(fileName);
    if (bytes.size() < sizeof(kMagic) + 4 || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) {
        return makeError(name + ": not a Fray patch library");
    }
    std::uint32_t version = 0;
    std::memcpy(&version, bytes.data() + sizeof(kMagic), sizeof version);
    if (version != kPatchFileVersion) {
        // Version 3 files carry neither the tables nor a checksum: damage in
        // them cannot be told from data, so they are not read.
        return makeError(ErrorKind::Unsupported,
                         name + ": patch library version " + std::to_string(version) + ", this build reads version " +
                             std::to_string(kPatchFileVersion) + " (generate the patches again: fray-cli patches generate PROJECT)");
    }
    if (bytes.size() < kHeader + kTrailer) return makeError(name + ": the patch library is truncated (" + std::to_string(bytes.size()) + " bytes)");
    const std::string_view body = bytes.substr(0, bytes.size() - kTrailer);
    std::uint32_t stored = 0;
    std::memcpy(&stored, bytes.data() + body.size(), sizeof stored);
    if (stored != patchFileChecksum(body)) {
        return makeError(name + ": the patch library is truncated or corrupt (its checksum does not match its contents; "
                                "generate the patches again)");
    }
    Reader r{{body.substr(sizeof(kMagic) + 4)}};
    const auto rule = r.get<std::uint32_t>();
    PatchLibrary lib;
    PatchLibrary::Data& data = detail::built(lib);
    data.libraryKey = r.get<std::uint64_t>();
    if (data.libraryKey != libraryFingerprint(actions)) {
        return makeError(ErrorKind::Stale, name + ": made from other actions than the project has now (generate the patches again)");
    }
    readPatches(r, actions.size(), data);
    if (!r.bad && rule == kPatchLinkRule) readTables(r, data);
    if (r.bad) return makeError(name + ": the patch library is corrupt at byte " + std::to_string(r.at + sizeof(kMagic) + 4));
    if (rule != kPatchLinkRule) {
        const std::string why = name + ": its connection tables follow link rule " + std::to_string(rule) + ", this build uses rule " +
                                std::to_string(kPatchLinkRule);
        if (options.staleTables == StaleTables::Refuse) return makeError(ErrorKind::Stale, why + " (generate the patches again)");
        if (!reportProgress(options.progress, 0.0, "connection tables")) return cancelled();
        buildConnections(actions, lib);
        if (!reportProgress(options.progress, 1.0, "connection tables")) return cancelled();
        if (options.notice) options.notice(why + ": rebuilt them (generate the patches again to store them)");
        return lib;
    }
    if (r.at != r.in.size()) return makeError(name + ": unexpected data after the patch library's tables");
    return lib;
}

Result<PatchLibrary> loadPatchLibrary(const std::filesystem::path& file, const ActionLibrary& actions, const PatchFileOptions& options) {
    auto bytes = readWholeFile(file, "the patch library");
    if (!bytes) return bytes.error();
    return readPatchLibrary(*bytes, file.string(), actions, options);
}

}  // namespace fray::sim
