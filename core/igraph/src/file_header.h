#pragma once
// The frame both graph files share (docs/IGRAPH.md, "Graph file", "Carry
// graph file"): 8 bytes of magic, the file version (u32) and the rule the
// graph was made by (u32), the body, then a CRC-32 (the patch library
// file's checksum) of everything before it. One writer and one reader, so
// that the duel's graph and the carry graph check their headers alike; each
// file says its own refusals (headerRefusal).
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "fray/core/byte_io.h"
#include "fray/core/result.h"
#include "fray/sim/patches.h"  // patchFileChecksum (CRC-32)

namespace fray::igraph::detail {

struct FileHeader {
    std::string_view magic;       // 8 bytes
    std::uint32_t version = 0;    // the layout
    std::uint32_t rule = 0;       // what the states and edges were made by
    std::string_view otherMagic;  // the other graph file's magic, refused by name
};

// Why a file's header is refused; `found` is the version or the rule read.
enum class HeaderProblem { OtherKind, NotThisKind, Version, Truncated, Checksum, Rule };
inline constexpr std::size_t kHeaderBytes = 8 + 4 + 4;
inline constexpr std::size_t kTrailerBytes = 4;

// Magic, version and rule; the body follows.
inline void writeHeader(ByteWriter& w, const FileHeader& h) {
    w.out.append(h.magic.data(), h.magic.size());
    w.put(h.version);
    w.put(h.rule);
}

// The checksum of everything written so far, last.
inline void sealFile(ByteWriter& w) { w.put(sim::patchFileChecksum(w.out)); }

// Checks the header, the size and the checksum, in that order (the other
// graph file, the magic, the version, truncation, the checksum, the rule).
// Returns a reader over the file without its checksum, just past the rule;
// a refusal is the error refuse(problem, found) says (Version: of kind
// Unsupported; Rule: Stale).
template <class Refuse>
Result<ByteReader> readHeader(std::string_view bytes, const FileHeader& h, Refuse&& refuse) {
    const auto starts = [&](std::string_view magic) { return bytes.size() >= magic.size() && bytes.substr(0, magic.size()) == magic; };
    if (starts(h.otherMagic)) return makeError(refuse(HeaderProblem::OtherKind, 0));
    if (bytes.size() < 12 || !starts(h.magic)) return makeError(refuse(HeaderProblem::NotThisKind, 0));
    std::uint32_t version = 0;
    std::memcpy(&version, bytes.data() + 8, sizeof version);
    if (version != h.version) return makeError(ErrorKind::Unsupported, refuse(HeaderProblem::Version, version));
    if (bytes.size() < kHeaderBytes + kTrailerBytes) return makeError(refuse(HeaderProblem::Truncated, bytes.size()));
    const std::string_view body = bytes.substr(0, bytes.size() - kTrailerBytes);
    std::uint32_t stored = 0;
    std::memcpy(&stored, bytes.data() + body.size(), sizeof stored);
    if (stored != sim::patchFileChecksum(body)) return makeError(refuse(HeaderProblem::Checksum, 0));
    ByteReader r{body, 12};
    const auto rule = r.get<std::uint32_t>();
    if (rule != h.rule) return makeError(ErrorKind::Stale, refuse(HeaderProblem::Rule, rule));
    return r;
}

}  // namespace fray::igraph::detail
