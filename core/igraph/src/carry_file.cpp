// The carry graph file (docs/IGRAPH.md, "Carry graph file"): little-endian
// fixed-size fields, bounds-checked on read, sealed by a CRC-32 (the patch
// library file's checksum), as the duel's graph file.
#include <algorithm>
#include <cmath>
#include <limits>

#include "carry_internal.h"
#include "file_header.h"
#include "fray/core/atomic_file.h"
#include "fray/core/byte_io.h"
#include "fray/igraph/carry.h"
#include "fray/sim/patches.h"  // libraryFingerprint

namespace fray::igraph {

namespace {

constexpr std::size_t kStateBytes = 3 * 8 + 4;
constexpr std::size_t kEdgeBytes = 4 + 2 + 2 + 4 * 4;

detail::FileHeader fileHeader() { return {kCarryGraphMagic, kCarryGraphFileVersion, kCarryGraphRule, kGraphMagic}; }

std::string again() { return " (build it again: fray-cli igraph build PROJECT --kind carry)"; }

void writeOptions(ByteWriter& w, const CarryOptions& o) {
    w.put(o.seed), w.str(o.prefix), w.put(o.boxLength), w.put(o.expandFraction), w.put(o.maxSamples), w.put(o.minNewShare);
    w.put(static_cast<std::int32_t>(o.maxRounds)), w.put(static_cast<std::int32_t>(o.startStates)), w.put(static_cast<std::int32_t>(o.maxFrontier));
    w.put(o.scale.sigmaR), w.put(o.scale.sigmaTheta), w.put(o.scale.frameSigma), w.put(static_cast<std::int32_t>(o.kmeansIterations));
    w.put(static_cast<std::int32_t>(o.variantsPerClass)), w.put(o.joinRadius);
}

void readOptions(ByteReader& r, CarryOptions& o) {
    o.seed = r.get<std::uint64_t>(), o.prefix = r.str(), o.boxLength = r.get<double>(), o.expandFraction = r.get<double>();
    o.maxSamples = r.get<std::int64_t>(), o.minNewShare = r.get<double>(), o.maxRounds = r.get<std::int32_t>();
    o.startStates = r.get<std::int32_t>(), o.maxFrontier = r.get<std::int32_t>();
    o.scale.sigmaR = r.get<double>(), o.scale.sigmaTheta = r.get<double>(), o.scale.frameSigma = r.get<double>();
    o.kmeansIterations = r.get<std::int32_t>(), o.variantsPerClass = r.get<std::int32_t>(), o.joinRadius = r.get<double>();
}

bool finite(double v) { return std::isfinite(v); }

Result<CarryGraph> readAny(std::string_view bytes, std::string_view fileName, const sim::ActionLibrary* lib) {
    const std::string name(fileName);
    auto header = detail::readHeader(bytes, fileHeader(), [&](detail::HeaderProblem p, std::uint64_t found) {
        switch (p) {
            case detail::HeaderProblem::OtherKind:
                return name + ": an interaction graph for a duel or team fight (fray-cli igraph build PROJECT), not a carry graph" + again();
            case detail::HeaderProblem::NotThisKind: return name + ": not a Fray carry graph file";
            case detail::HeaderProblem::Version:
                return name + ": carry graph file version " + std::to_string(found) + ", this build reads version " + std::to_string(kCarryGraphFileVersion) +
                       again();
            case detail::HeaderProblem::Truncated: return name + ": the carry graph file is truncated (" + std::to_string(found) + " bytes)" + again();
            case detail::HeaderProblem::Checksum:
                return name + ": the carry graph file is truncated or corrupt (its checksum does not match its contents)" + again();
            case detail::HeaderProblem::Rule:
                return name + ": made by carry graph rule " + std::to_string(found) + ", this build uses rule " + std::to_string(kCarryGraphRule) + again();
        }
        return name + ": not a Fray carry graph file";
    });
    if (!header) return header.error();
    ByteReader& r = *header;
    CarryGraph g;
    g.libraryKey = r.get<std::uint64_t>();
    readOptions(r, g.options);
    g.gripReach = r.get<double>(), g.gripHeight = r.get<double>();
    g.samples = r.get<std::int64_t>(), g.rounds = r.get<std::int64_t>(), g.simulated = r.get<std::int64_t>();
    g.hold = r.get<std::int32_t>();
    const std::size_t na = r.count(4);
    for (std::size_t k = 0; k < na && !r.bad; ++k) g.actions.push_back(r.get<std::int32_t>());
    if (r.bad) return makeError(name + ": the carry graph file is corrupt at byte " + std::to_string(r.at) + again());
    const auto& o = g.options;
    if (!(o.boxLength > 0.2 && o.boxLength < 10) || !(o.scale.sigmaR > 0) || !(o.scale.sigmaTheta > 0) || !finite(o.joinRadius) ||
        !finite(g.gripReach) || !finite(g.gripHeight) || g.actions.empty()) {
        return makeError(name + ": the carry graph file holds values out of range (box length, sigmas or actions)" + again());
    }
    if (lib) {
        if (g.libraryKey != sim::libraryFingerprint(*lib)) {
            return makeError(ErrorKind::Stale, name + ": made from other actions than the project has now" + again());
        }
        if (g.actions != detail::carryActions(*lib, o.prefix) || g.hold != detail::carryHold(*lib, g.actions)) {
            return makeError(ErrorKind::Stale, name + ": built for other carry-end actions than the project has now" + again());
        }
    }
    const int libSize = lib ? lib->size() : std::numeric_limits<std::int16_t>::max() + 1;
    for (int a : g.actions)
        if (a < 0 || a >= libSize) r.bad = true;
    if (std::find(g.actions.begin(), g.actions.end(), g.hold) == g.actions.end()) r.bad = true;
    const std::size_t ns = r.count(kStateBytes);
    g.states.reserve(ns);
    g.firstEdge.assign(ns + 1, 0);
    std::vector<std::uint32_t> counts(ns);
    for (std::size_t i = 0; i < ns && !r.bad; ++i) {
        InteractionState s;
        s.r = r.get<double>(), s.thetaA = r.get<double>(), s.thetaB = r.get<double>();
        counts[i] = r.get<std::uint32_t>();
        if (!finite(s.r) || !finite(s.thetaA) || !finite(s.thetaB) || s.r < 0) r.bad = true;
        g.states.push_back(s);
    }
    std::size_t total = 0;
    for (std::size_t i = 0; i < ns && !r.bad; ++i) {
        g.firstEdge[i] = static_cast<std::uint32_t>(total), total += counts[i];
        if (total > (r.in.size() - r.at) / kEdgeBytes) r.bad = true;
    }
    g.firstEdge[ns] = static_cast<std::uint32_t>(total);
    if (!r.bad) g.edges.resize(total);
    for (std::size_t k = 0; k < total && !r.bad; ++k) {
        CarryEdge& e = g.edges[k];
        e.to = r.get<std::int32_t>(), e.actionA = r.get<std::int16_t>(), e.actionB = r.get<std::int16_t>();
        e.boxX = r.get<float>(), e.boxZ = r.get<float>(), e.gripError = r.get<float>(), e.seconds = r.get<float>();
        const auto known = [&](int a) { return std::find(g.actions.begin(), g.actions.end(), a) != g.actions.end(); };
        if (e.to < 0 || static_cast<std::size_t>(e.to) >= ns || !known(e.actionA) || !known(e.actionB) || !finite(e.boxX) || !finite(e.boxZ) ||
            !finite(e.gripError) || !(e.seconds > 0 && e.seconds < 60)) {
            r.bad = true;
        }
    }
    if (r.bad) return makeError(name + ": the carry graph file is corrupt at byte " + std::to_string(r.at) + again());
    if (r.at != r.in.size()) return makeError(name + ": unexpected data after the carry graph's edges" + again());
    return g;
}

}  // namespace

Result<std::string> carryGraphBytes(const CarryGraph& g) {
    if (g.firstEdge.size() != g.states.size() + 1 || g.firstEdge.back() != g.edges.size()) {
        return makeError(ErrorKind::Internal, "the carry graph's edge offsets are malformed");
    }
    ByteWriter w;
    w.out.reserve(256 + g.states.size() * kStateBytes + g.edges.size() * kEdgeBytes);
    detail::writeHeader(w, fileHeader());
    w.put(g.libraryKey);
    writeOptions(w, g.options);
    w.put(g.gripReach), w.put(g.gripHeight), w.put(g.samples), w.put(g.rounds), w.put(g.simulated);
    w.put(static_cast<std::int32_t>(g.hold));
    w.put(static_cast<std::uint32_t>(g.actions.size()));
    for (int a : g.actions) w.put(static_cast<std::int32_t>(a));
    w.put(static_cast<std::uint32_t>(g.states.size()));
    for (std::size_t i = 0; i < g.states.size(); ++i) {
        const auto& s = g.states[i];
        w.put(s.r), w.put(s.thetaA), w.put(s.thetaB), w.put(g.firstEdge[i + 1] - g.firstEdge[i]);
    }
    for (const auto& e : g.edges) {
        w.put(e.to), w.put(e.actionA), w.put(e.actionB), w.put(e.boxX), w.put(e.boxZ), w.put(e.gripError), w.put(e.seconds);
    }
    detail::sealFile(w);
    return std::move(w.out);
}

Status saveCarryGraph(const CarryGraph& g, const std::filesystem::path& file) {
    auto bytes = carryGraphBytes(g);
    if (!bytes) return makeError(bytes.error().kind, file.string() + ": " + bytes.error().message);
    return writeFileAtomically(file, *bytes);
}

Result<CarryGraph> readCarryGraph(std::string_view bytes, std::string_view fileName, const sim::ActionLibrary& lib) {
    return readAny(bytes, fileName, &lib);
}

Result<CarryGraph> readCarryGraphUnbound(std::string_view bytes, std::string_view fileName) { return readAny(bytes, fileName, nullptr); }

Result<CarryGraph> loadCarryGraph(const std::filesystem::path& file, const sim::ActionLibrary& lib) {
    auto bytes = readWholeFile(file, "the carry graph");
    if (!bytes) return bytes.error();
    return readCarryGraph(*bytes, file.string(), lib);
}

}  // namespace fray::igraph
