// The Interaction Graph file (docs/IGRAPH.md, "Graph file"): little-endian
// fixed-size fields, bounds-checked on read, sealed by a CRC-32 (the patch
// library file's checksum).
#include <cmath>
#include <limits>

#include "fray/core/atomic_file.h"
#include "fray/core/byte_io.h"
#include "file_header.h"
#include "fray/igraph/carry.h"  // kCarryGraphMagic
#include "fray/sim/patches.h"  // libraryFingerprint
#include "game.h"

namespace fray::igraph {

namespace {

constexpr std::size_t kEdgeBytes = sizeof(Edge);
constexpr std::size_t kStateBytes = 4 * 8 + 3 * 4;

using Writer = ByteWriter;  // fray/core/byte_io.h
using Reader = ByteReader;

void writeOptions(Writer& w, const BuildOptions& o) {
    w.put(o.seed), w.put(o.expandFraction), w.put(o.maxSamples), w.put(o.minNewShare), w.put(static_cast<std::int32_t>(o.maxRounds));
    w.put(static_cast<std::int32_t>(o.startStates)), w.put(static_cast<std::int32_t>(o.maxFrontier)), w.put(o.maxDistance);
    w.put(o.scale.sigmaR), w.put(o.scale.sigmaTheta), w.put(o.scale.frameSigma), w.put(o.cellScale);
    w.put(static_cast<std::int32_t>(o.kmeansIterations)), w.put(o.joinRadius), w.put(static_cast<std::int32_t>(o.coverageDepth));
    w.put(static_cast<std::int32_t>(o.coverageStarts)), w.put(static_cast<std::int32_t>(o.variantsPerClass));
    w.put(static_cast<std::int32_t>(o.outcomeSamples)), w.put(o.outcomeSpreadR), w.put(o.outcomeSpreadTheta);
}

void readOptions(Reader& r, BuildOptions& o) {
    o.seed = r.get<std::uint64_t>(), o.expandFraction = r.get<double>(), o.maxSamples = r.get<std::int64_t>();
    o.minNewShare = r.get<double>(), o.maxRounds = r.get<std::int32_t>(), o.startStates = r.get<std::int32_t>();
    o.maxFrontier = r.get<std::int32_t>(), o.maxDistance = r.get<double>();
    o.scale.sigmaR = r.get<double>(), o.scale.sigmaTheta = r.get<double>(), o.scale.frameSigma = r.get<double>();
    o.cellScale = r.get<double>(), o.kmeansIterations = r.get<std::int32_t>(), o.joinRadius = r.get<double>();
    o.coverageDepth = r.get<std::int32_t>(), o.coverageStarts = r.get<std::int32_t>();
    o.variantsPerClass = r.get<std::int32_t>();
    o.outcomeSamples = r.get<std::int32_t>(), o.outcomeSpreadR = r.get<double>(), o.outcomeSpreadTheta = r.get<double>();
}

bool finite(double v) { return std::isfinite(v); }

detail::FileHeader fileHeader() { return {kGraphMagic, kGraphFileVersion, kGraphRule, kCarryGraphMagic}; }

// Reads the file; `rules` (when set) bounds the indices.
Result<Graph> readAny(std::string_view bytes, std::string_view fileName, const Rules* rules) {
    const std::string name(fileName);
    auto header = detail::readHeader(bytes, fileHeader(), [&](detail::HeaderProblem p, std::uint64_t found) {
        switch (p) {
            case detail::HeaderProblem::OtherKind:
                return name + ": a carry graph (two carriers of a box: igraph play --kind carry), not a duel's interaction graph";
            case detail::HeaderProblem::NotThisKind: return name + ": not a Fray interaction graph file";
            case detail::HeaderProblem::Version:
                return name + ": interaction graph file version " + std::to_string(found) + ", this build reads version " +
                       std::to_string(kGraphFileVersion) + " (build the graph again: fray-cli igraph build PROJECT)";
            case detail::HeaderProblem::Truncated: return name + ": the graph file is truncated (" + std::to_string(found) + " bytes)";
            case detail::HeaderProblem::Checksum:
                return name + ": the graph file is truncated or corrupt (its checksum does not match its contents; "
                              "build the graph again: fray-cli igraph build PROJECT)";
            case detail::HeaderProblem::Rule:
                return name + ": made by graph rule " + std::to_string(found) + ", this build uses rule " + std::to_string(kGraphRule) +
                       " (build the graph again: fray-cli igraph build PROJECT)";
        }
        return name + ": not a Fray interaction graph file";
    });
    if (!header) return header.error();
    Reader& r = *header;
    Graph g;
    g.libraryKey = r.get<std::uint64_t>();
    g.actionsKey = r.get<std::uint64_t>();
    if (rules) {
        if (g.libraryKey != sim::libraryFingerprint(rules->library())) {
            return makeError(ErrorKind::Stale, name + ": made from other actions than the project has now (build the graph again)");
        }
        if (g.actionsKey != rules->key()) {
            return makeError(ErrorKind::Stale, name + ": built for another choice of actions than asked for (build the graph again)");
        }
    }
    readOptions(r, g.options);
    g.stats.samples = r.get<std::int64_t>(), g.stats.rounds = r.get<std::int64_t>(), g.stats.simulated = r.get<std::int64_t>();
    g.stats.coverage = r.get<double>(), g.stats.coverageVisited = r.get<std::int64_t>();
    const int libSize = rules ? rules->library().size() : std::numeric_limits<int>::max();
    const int sets = rules ? rules->nextSetCount() : std::numeric_limits<int>::max();
    const std::size_t na = r.count(4);
    for (std::size_t k = 0; k < na && !r.bad; ++k) {
        const auto a = r.get<std::int32_t>();
        if (a < 0 || a >= libSize) r.bad = true;
        g.actions.push_back(a);
    }
    const std::size_t ns = r.count(kStateBytes);
    g.states.reserve(ns);
    g.firstEdge.assign(ns + 1, 0);
    std::vector<std::uint32_t> counts(ns);
    for (std::size_t i = 0; i < ns && !r.bad; ++i) {
        InteractionState s;
        s.r = r.get<double>(), s.thetaA = r.get<double>(), s.thetaB = r.get<double>();
        s.nextSet = r.get<std::int32_t>(), s.actionB = r.get<std::int32_t>(), s.frameB = r.get<double>();
        counts[i] = r.get<std::uint32_t>();
        if (!finite(s.r) || !finite(s.thetaA) || !finite(s.thetaB) || !finite(s.frameB) || s.nextSet < 0 || s.nextSet >= sets ||
            s.actionB < 0 || s.actionB >= libSize) {
            r.bad = true;
        }
        g.states.push_back(s);
    }
    std::size_t total = 0;
    for (std::size_t i = 0; i < ns; ++i) g.firstEdge[i] = static_cast<std::uint32_t>(total), total += counts[i];
    g.firstEdge[ns] = static_cast<std::uint32_t>(total);
    if (!r.bad && total > (r.in.size() - r.at) / kEdgeBytes) r.bad = true;
    if (!r.bad) g.edges.resize(total);
    for (std::size_t k = 0; k < total && !r.bad; ++k) {
        Edge& e = g.edges[k];
        e.to = r.get<std::int32_t>(), e.actionBits = r.get<std::uint16_t>();
        e.givenQ = r.get<std::uint8_t>(), e.receivedQ = r.get<std::uint8_t>();
        if (e.action() >= libSize || e.to < 0 || static_cast<std::size_t>(e.to) >= ns) r.bad = true;
    }
    if (r.bad) return makeError(name + ": the graph file is corrupt at byte " + std::to_string(r.at));
    if (r.at != r.in.size()) return makeError(name + ": unexpected data after the graph's edges");
    g.index();
    if (rules) g.timeEdges(rules->library());
    g.findNeighbours();
    return g;
}

}  // namespace

Result<std::string> graphBytes(const Graph& g) {
    if (g.firstEdge.size() != g.states.size() + 1 || g.firstEdge.back() != g.edges.size()) {
        return makeError(ErrorKind::Internal, "the interaction graph's edge offsets are malformed");
    }
    Writer w;
    w.out.reserve(64 + g.states.size() * kStateBytes + g.edges.size() * kEdgeBytes);
    detail::writeHeader(w, fileHeader());
    w.put(g.libraryKey);
    w.put(g.actionsKey);
    writeOptions(w, g.options);
    w.put(g.stats.samples), w.put(g.stats.rounds), w.put(g.stats.simulated), w.put(g.stats.coverage), w.put(g.stats.coverageVisited);
    w.put(static_cast<std::uint32_t>(g.actions.size()));
    for (int a : g.actions) w.put(static_cast<std::int32_t>(a));
    w.put(static_cast<std::uint32_t>(g.states.size()));
    for (std::size_t i = 0; i < g.states.size(); ++i) {
        const auto& s = g.states[i];
        w.put(s.r), w.put(s.thetaA), w.put(s.thetaB), w.put(static_cast<std::int32_t>(s.nextSet)), w.put(static_cast<std::int32_t>(s.actionB));
        w.put(s.frameB), w.put(g.firstEdge[i + 1] - g.firstEdge[i]);
    }
    for (const auto& e : g.edges) {
        w.put(e.to), w.put(e.actionBits), w.put(e.givenQ), w.put(e.receivedQ);
    }
    detail::sealFile(w);
    return std::move(w.out);
}

Status saveGraph(const Graph& g, const std::filesystem::path& file) {
    auto bytes = graphBytes(g);
    if (!bytes) return makeError(bytes.error().kind, file.string() + ": " + bytes.error().message);
    return writeFileAtomically(file, *bytes);
}

Result<Graph> readGraph(std::string_view bytes, std::string_view fileName, const Rules& rules) { return readAny(bytes, fileName, &rules); }

Result<Graph> readGraphUnbound(std::string_view bytes, std::string_view fileName) { return readAny(bytes, fileName, nullptr); }

Result<Graph> loadGraph(const std::filesystem::path& file, const Rules& rules) {
    auto bytes = readWholeFile(file, "the interaction graph");
    if (!bytes) return bytes.error();
    return readGraph(*bytes, file.string(), rules);
}

}  // namespace fray::igraph
