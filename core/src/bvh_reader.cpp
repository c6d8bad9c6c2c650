// Streaming BVH reader. The file is read in fixed-size chunks; tokens are
// views into the chunk buffer. Frame rows are parsed line by line so a short
// row is reported with its line number and the exact counts.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <unordered_set>
#include <vector>

#include <glm/geometric.hpp>

#include "fray/core/rotation.h"
#include "fray/io/bvh.h"

namespace fray {
namespace {

constexpr std::size_t kChunk = std::size_t{1} << 20;
// Larger magnitudes are no capture (a billion cm or degrees) and would turn
// into infinities once stored as float.
constexpr double kMaxValue = 1e9;

// Printable excerpt of a token for messages (binary junk must not reach a terminal raw).
std::string excerpt(std::string_view s) {
    std::string out;
    for (char c : s.substr(0, 32)) {
        const auto u = static_cast<unsigned char>(c);
        out.push_back(u >= 0x20 && u < 0x7f ? c : '?');
    }
    if (s.size() > 32) out += "...";
    return out;
}

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

class Lexer {
public:
    // Memory source: no copy, no refill.
    explicit Lexer(std::string_view data) : p_(data.data()), e_(data.data() + data.size()), eof_(true) {}
    // File source: owns a chunk buffer.
    explicit Lexer(std::FILE* file) : file_(file), buf_(new char[kChunk]) { p_ = e_ = buf_.get(); }

    int line() const { return line_; }
    bool newlineBefore() const { return newlineBefore_; }
    bool tooLong() const { return tooLong_; }

    // Next whitespace-separated token; false at end of input. The view stays
    // valid until the next call.
    bool next(std::string_view& tok) {
        newlineBefore_ = false;
        for (;;) {
            while (p_ < e_) {
                const char c = *p_;
                if (c == '\n') {
                    ++line_;
                    newlineBefore_ = true;
                    ++p_;
                } else if (isBlank(c)) {
                    ++p_;
                } else {
                    goto found;
                }
            }
            if (!refill()) return false;
        }
    found:
        const char* s = p_;
        for (;;) {
            while (p_ < e_ && *p_ != '\n' && !isBlank(*p_)) ++p_;
            if (p_ < e_ || eof_) break;
            // The token runs into the end of the buffer: keep it and read more.
            const std::size_t have = static_cast<std::size_t>(p_ - s);
            if (have >= kChunk / 2) {
                tooLong_ = true;
                return false;
            }
            std::memmove(buf_.get(), s, have);
            s = buf_.get();
            p_ = buf_.get() + have;
            e_ = p_;
            readMore();
        }
        tok = std::string_view(s, static_cast<std::size_t>(p_ - s));
        return true;
    }

    // Next non-blank line as [begin, end) without its line break; false at end
    // of input. The whole line is in the buffer, so callers scan it without
    // bounds checks against the chunk. Used for frame rows (the hot path).
    bool nextLine(const char*& begin, const char*& end) {
        for (;;) {
            while (p_ < e_ && (*p_ == '\n' || isBlank(*p_))) {
                if (*p_ == '\n') ++line_;
                ++p_;
            }
            if (p_ < e_) break;
            if (!refill()) return false;
        }
        for (;;) {
            const void* nl = std::memchr(p_, '\n', static_cast<std::size_t>(e_ - p_));
            if (nl || eof_) {
                begin = p_;
                end = nl ? static_cast<const char*>(nl) : e_;
                p_ = end;  // the '\n' itself is counted by the next call
                return true;
            }
            const std::size_t have = static_cast<std::size_t>(e_ - p_);
            if (have >= kChunk / 2) {
                tooLong_ = true;
                return false;
            }
            std::memmove(buf_.get(), p_, have);
            p_ = buf_.get();
            e_ = p_ + have;
            readMore();
        }
    }

    // Rest of the current line after the last token (trimmed); used for joint
    // names, which may contain spaces.
    std::string restOfLine() {
        std::string out;
        for (;;) {
            while (p_ < e_ && *p_ != '\n') out.push_back(*p_++);
            if (p_ < e_ || !refill()) break;
            if (out.size() > 4096) break;
        }
        while (!out.empty() && isBlank(out.back())) out.pop_back();
        std::size_t i = 0;
        while (i < out.size() && isBlank(out[i])) ++i;
        return out.substr(i);
    }

private:
    bool refill() {
        if (eof_) return false;
        p_ = e_ = buf_.get();
        readMore();
        return p_ < e_;
    }
    void readMore() {
        const std::size_t room = kChunk - static_cast<std::size_t>(e_ - buf_.get());
        const std::size_t n = std::fread(const_cast<char*>(e_), 1, room, file_);
        e_ += n;
        if (n < room) eof_ = true;
    }

    std::FILE* file_ = nullptr;
    std::unique_ptr<char[]> buf_;
    const char* p_ = nullptr;
    const char* e_ = nullptr;
    bool eof_ = false;
    int line_ = 1;
    bool newlineBefore_ = false;
    bool tooLong_ = false;
};

// Slow path: any token std::from_chars accepts (exponents, long mantissas,
// nan/inf), with an optional leading '+'.
bool parseNumberSlow(std::string_view tok, double& out) {
    const char* b = tok.data();
    const char* e = b + tok.size();
    if (b < e && *b == '+') ++b;
    auto [ptr, ec] = std::from_chars(b, e, out);
    return ec == std::errc() && ptr == e;
}

// Appends the digits at p to mant, four at a time while four digits are
// available (SWAR: one load, two checks and three multiplies per block), then
// one at a time.
inline void readDigits(const char*& p, const char* end, std::uint64_t& mant) {
    while (end - p >= 4) {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        if ((v & 0xF0F0F0F0u) != 0x30303030u || ((v + 0x06060606u) & 0xF0F0F0F0u) != 0x30303030u) break;
        std::uint32_t t = v - 0x30303030u;    // bytes d0 d1 d2 d3 (d0 first in memory)
        t = t * 10 + (t >> 8);                // byte0 = 10*d0 + d1, byte2 = 10*d2 + d3
        mant = mant * 10000 + (t & 0xFFu) * 100 + ((t >> 16) & 0xFFu);
        p += 4;
    }
    unsigned d;
    while (p < end && (d = static_cast<unsigned>(*p - '0')) < 10u) mant = mant * 10 + d, ++p;
}

// Parses the number starting at q (a non-blank character) and moves q past
// its token. Exact fast path for plain decimals (Clinger): a mantissa below
// 2^53 and a power of ten up to 1e22 are both exact in a double, so one divide
// gives the correctly rounded value. Anything else goes to from_chars.
inline bool parseNumberAt(const char*& q, const char* end, double& out, std::string_view& token) {
    static constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                        1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    const char* start = q;
    const char* p = q;
    const bool neg = *p == '-';
    if (*p == '-' || *p == '+') ++p;
    std::uint64_t mant = 0;
    const char* d0 = p;
    readDigits(p, end, mant);
    int intDigits = static_cast<int>(p - d0), fracDigits = 0;
    if (p < end && *p == '.') {
        const char* f0 = ++p;
        readDigits(p, end, mant);
        fracDigits = static_cast<int>(p - f0);
    }
    if ((p == end || isBlank(*p)) && intDigits + fracDigits > 0 && intDigits + fracDigits <= 19 &&
        mant <= (std::uint64_t{1} << 53) && fracDigits <= 22) {
        const double v = static_cast<double>(mant) / kPow10[fracDigits];
        out = neg ? -v : v;
        q = p;
        return true;
    }
    while (p < end && !isBlank(*p)) ++p;
    q = p;
    token = std::string_view(start, static_cast<std::size_t>(p - start));
    return parseNumberSlow(token, out);
}

bool parseNumber(std::string_view tok, double& out) {
    if (tok.empty()) return false;
    const char* q = tok.data();
    const char* end = q + tok.size();
    std::string_view t;
    return parseNumberAt(q, end, out, t) && q == end;
}

class BvhParser {
public:
    BvhParser(Lexer& lex, std::string_view name, std::size_t fileSize, const BvhReadOptions& opt)
        : lex_(lex), name_(name), fileSize_(fileSize), opt_(opt) {}

    Result<Motion> run() {
        std::string_view tok;
        if (!lex_.next(tok)) return lex_.tooLong() ? fail("token too long (binary data?)") : fail("file is empty");
        if (tok != "HIERARCHY") return fail("expected 'HIERARCHY' at the start of the file, found '" + excerpt(tok) + "'");
        if (!lex_.next(tok)) return failEof("ROOT");
        if (tok != "ROOT") return fail("expected 'ROOT', found '" + excerpt(tok) + "'");
        if (auto st = parseJoint(-1); !st) return st.error();
        if (!lex_.next(tok)) return failEof("MOTION (the file has no MOTION section)");
        if (tok == "ROOT") return fail("more than one ROOT; only single-skeleton files are supported");
        if (tok == "}") return fail("unbalanced braces: '}' after the root joint was closed");
        if (tok != "MOTION") return fail("expected 'MOTION', found '" + excerpt(tok) + "'");
        return parseMotion();
    }

private:
    Error fail(const std::string& what) const {
        return makeError(std::string(name_) + ":" + std::to_string(lex_.line()) + ": " + what);
    }
    Error failEof(const std::string& expected) const {
        if (lex_.tooLong()) return fail("token too long (binary data?)");
        return fail("unexpected end of file, expected " + expected);
    }

    Status readVec3(const char* what, glm::vec3& out) {
        std::string_view tok;
        for (int i = 0; i < 3; ++i) {
            if (!lex_.next(tok)) return failEof(std::string(what) + " value");
            double v;
            if (!parseNumber(tok, v)) return fail(std::string(what) + ": expected a number, found '" + excerpt(tok) + "'");
            if (!std::isfinite(v)) return fail(std::string(what) + ": value '" + excerpt(tok) + "' is not finite");
            if (std::abs(v) > kMaxValue) return fail(std::string(what) + ": value '" + excerpt(tok) + "' is out of range");
            out[i] = static_cast<float>(v);
        }
        return {};
    }

    static bool validName(const std::string& n) {
        if (n.empty()) return false;
        for (char c : n) {
            const auto u = static_cast<unsigned char>(c);
            if (u < 0x20 || u == 0x7f) return false;
        }
        return true;
    }

    // Parses "name { OFFSET ... CHANNELS ... (JOINT|End Site)* }" after ROOT/JOINT.
    Status parseJoint(int parent) {
        std::string name = lex_.restOfLine();
        bool braceOnNameLine = false;
        if (!name.empty() && name.back() == '{') {
            braceOnNameLine = true;
            name.pop_back();
            while (!name.empty() && isBlank(name.back())) name.pop_back();
        }
        if (name.empty()) return fail("joint has no name");
        if (!validName(name)) return fail("joint name contains control characters");
        // A brace in a name cannot be written back unambiguously ("JOINT A{" reads
        // as joint "A" followed by its opening brace), so it is refused here.
        if (name.find_first_of("{}") != std::string::npos)
            return fail("joint name '" + excerpt(name) + "' contains a brace; put '{' on its own line or after the name and a space");
        if (!names_.insert(name).second) return fail("duplicate joint name '" + excerpt(name) + "'");
        if (static_cast<std::size_t>(sk_.jointCount()) >= opt_.maxJoints)
            return fail("more than " + std::to_string(opt_.maxJoints) + " joints; refusing the file");
        if (++depth_ > 256) return fail("joint hierarchy nested deeper than 256 levels");
        std::string_view tok;
        if (!braceOnNameLine) {
            if (!lex_.next(tok)) return failEof("'{' after joint '" + excerpt(name) + "'");
            if (tok != "{") return fail("expected '{' after joint '" + excerpt(name) + "', found '" + excerpt(tok) + "'");
        }
        if (!lex_.next(tok)) return failEof("OFFSET in joint '" + excerpt(name) + "'");
        if (tok != "OFFSET") return fail("expected 'OFFSET' in joint '" + excerpt(name) + "', found '" + excerpt(tok) + "'");
        glm::vec3 offset;
        if (auto st = readVec3("OFFSET", offset); !st) return st;
        if (!lex_.next(tok)) return failEof("CHANNELS in joint '" + excerpt(name) + "'");
        std::vector<Channel> channels;
        if (tok == "CHANNELS") {
            if (!lex_.next(tok)) return failEof("channel count");
            double count;
            if (!parseNumber(tok, count) || count != std::floor(count))
                return fail("CHANNELS: expected a channel count, found '" + excerpt(tok) + "'");
            if (count < 0 || count > 6)
                return fail("CHANNELS: count must be between 0 and 6, found " + excerpt(tok));
            for (int i = 0; i < static_cast<int>(count); ++i) {
                if (!lex_.next(tok)) return failEof("channel name");
                const auto c = parseChannel(tok);
                if (!c)
                    return fail("CHANNELS declares " + std::to_string(static_cast<int>(count)) + " channels, found " +
                                std::to_string(i) + " before '" + excerpt(tok) + "'");
                if (std::find(channels.begin(), channels.end(), *c) != channels.end())
                    return fail("channel '" + std::string(toString(*c)) + "' listed twice in joint '" + excerpt(name) + "'");
                channels.push_back(*c);
            }
            if (!lex_.next(tok)) return failEof("JOINT, End Site or '}' in joint '" + excerpt(name) + "'");
        } else if (parent < 0) {
            return fail("root joint '" + excerpt(name) + "' has no CHANNELS");
        }
        const int self = sk_.addJoint(name, parent, offset, channels, rotationOrderFromChannels(channels));
        int rotCount = 0;
        for (Channel c : channels) rotCount += (c == Channel::Xrotation || c == Channel::Yrotation || c == Channel::Zrotation);
        if (rotCount != 0 && rotCount != 3)
            return fail("joint '" + excerpt(name) + "' has " + std::to_string(rotCount) + " rotation channels; need 0 or 3");
        totalChannels_ += channels.size();
        for (;;) {
            if (tok == "}") break;
            if (tok == "JOINT") {
                if (auto st = parseJoint(self); !st) return st;
            } else if (tok == "End") {
                if (!lex_.next(tok)) return failEof("'Site'");
                if (tok != "Site") return fail("expected 'End Site', found 'End " + excerpt(tok) + "'");
                if (!lex_.next(tok)) return failEof("'{' after End Site");
                if (tok != "{") return fail("expected '{' after End Site, found '" + excerpt(tok) + "'");
                if (!lex_.next(tok)) return failEof("OFFSET in End Site");
                if (tok != "OFFSET") return fail("expected 'OFFSET' in End Site, found '" + excerpt(tok) + "'");
                glm::vec3 end;
                if (auto st = readVec3("OFFSET", end); !st) return st;
                if (!lex_.next(tok)) return failEof("'}' closing End Site");
                if (tok != "}") return fail("expected '}' closing End Site, found '" + excerpt(tok) + "'");
                sk_.endSites[static_cast<std::size_t>(self)] = end;
            } else if (tok == "MOTION") {
                return fail("unbalanced braces: MOTION reached while joint '" + excerpt(name) + "' is still open");
            } else if (tok == "CHANNELS" || tok == "OFFSET") {
                return fail("unexpected '" + std::string(tok) + "' in joint '" + excerpt(name) + "' (given twice, or out of order)");
            } else {
                return fail("expected JOINT, End Site or '}' in joint '" + excerpt(name) + "', found '" + excerpt(tok) + "'");
            }
            if (!lex_.next(tok)) return failEof("'}' closing joint '" + excerpt(name) + "' (unbalanced braces)");
        }
        --depth_;
        return {};
    }

    Result<Motion> parseMotion() {
        std::string_view tok;
        if (!lex_.next(tok)) return failEof("'Frames:'");
        double frames = 0;
        if (tok == "Frames:") {
            if (!lex_.next(tok)) return failEof("the frame count");
            if (!parseNumber(tok, frames)) return fail("Frames: expected a number, found '" + excerpt(tok) + "'");
        } else if (tok.substr(0, 7) == "Frames:") {
            if (!parseNumber(tok.substr(7), frames)) return fail("Frames: expected a number, found '" + excerpt(tok) + "'");
        } else {
            return fail("expected 'Frames:', found '" + excerpt(tok) + "'");
        }
        if (!std::isfinite(frames) || frames != std::floor(frames)) return fail("Frames: '" + excerpt(tok) + "' is not a whole number");
        if (frames <= 0) return fail("Frames: must be positive, found " + excerpt(tok));
        if (frames > static_cast<double>(opt_.maxFrames))
            return fail("Frames: " + excerpt(tok) + " exceeds the limit of " + std::to_string(opt_.maxFrames) + " frames");
        const auto frameCount = static_cast<std::size_t>(frames);
        const std::size_t jc = static_cast<std::size_t>(sk_.jointCount());
        const double bytes = frames * static_cast<double>(jc) * (sizeof(glm::vec3) + sizeof(glm::quat));
        if (bytes > static_cast<double>(opt_.maxMotionBytes))
            return fail("Frames: " + excerpt(tok) + " x " + std::to_string(jc) + " joints needs " +
                        std::to_string(static_cast<long long>(bytes / (1 << 20))) + " MiB, over the limit of " +
                        std::to_string(opt_.maxMotionBytes >> 20) + " MiB");
        if (!lex_.next(tok)) return failEof("'Frame Time:'");
        if (tok != "Frame") return fail("expected 'Frame Time:', found '" + excerpt(tok) + "'");
        if (!lex_.next(tok)) return failEof("'Time:'");
        if (tok != "Time:") return fail("expected 'Frame Time:', found 'Frame " + excerpt(tok) + "'");
        if (!lex_.next(tok)) return failEof("the frame time");
        double frameTime;
        if (!parseNumber(tok, frameTime)) return fail("Frame Time: expected a number, found '" + excerpt(tok) + "'");
        if (!std::isfinite(frameTime) || frameTime <= 0 || frameTime > 10)
            return fail("Frame Time: must be a positive number of seconds, found " + excerpt(tok));

        Motion motion(sk_, 1.0 / frameTime, 0);
        // Reserve no more than the file could possibly hold (two bytes a value).
        const std::size_t perFrame = std::max<std::size_t>(totalChannels_, 1);
        const std::size_t plausible = fileSize_ == 0 ? frameCount : std::min(frameCount, fileSize_ / (2 * perFrame) + 1);
        motion.reserveFrames(plausible);

        std::vector<double> values(totalChannels_);
        std::vector<glm::vec3> t(jc);
        std::vector<glm::quat> r(jc);
        const Skeleton& sk = sk_;
        const std::size_t expected = totalChannels_;
        const char* lb = nullptr;
        const char* le = nullptr;
        for (std::size_t f = 0; f < frameCount; ++f) {
            if (!lex_.nextLine(lb, le)) {
                if (lex_.tooLong()) return fail("line too long (binary data?)");
                return fail("expected " + std::to_string(frameCount) + " frames, found " + std::to_string(f) +
                            " (file truncated?)");
            }
            const int rowLine = lex_.line();
            std::size_t n = 0;
            const char* q = lb;
            for (;;) {
                while (q < le && isBlank(*q)) ++q;
                if (q == le) break;
                const char* t0 = q;
                std::string_view num;
                double v;
                if (!parseNumberAt(q, le, v, num)) {
                    return fail("frame " + std::to_string(f) + ": expected a number, found '" + excerpt(num) + "'");
                }
                if (!std::isfinite(v) || std::abs(v) > kMaxValue) {
                    num = std::string_view(t0, static_cast<std::size_t>(q - t0));
                    return fail("frame " + std::to_string(f) + ": value '" + excerpt(num) + "' is " +
                                (std::isfinite(v) ? "out of range" : "not finite"));
                }
                if (n < expected) values[n] = v;
                ++n;
            }
            if (n != expected)
                return makeError(std::string(name_) + ":" + std::to_string(rowLine) + ": expected " +
                                 std::to_string(expected) + " channel values, found " + std::to_string(n));
            // Decode channels into local translation and rotation.
            std::size_t k = 0;
            for (std::size_t j = 0; j < jc; ++j) {
                glm::vec3 pos = sk.offsets[j];
                glm::dvec3 euler(0.0);
                for (Channel c : sk.channels[j]) {
                    const double v = values[k++];
                    switch (c) {
                        case Channel::Xposition: pos.x = static_cast<float>(v); break;
                        case Channel::Yposition: pos.y = static_cast<float>(v); break;
                        case Channel::Zposition: pos.z = static_cast<float>(v); break;
                        case Channel::Xrotation: euler.x = v; break;
                        case Channel::Yrotation: euler.y = v; break;
                        case Channel::Zrotation: euler.z = v; break;
                    }
                }
                t[j] = pos;
                r[j] = sk.channels[j].empty() ? glm::quat(1, 0, 0, 0) : eulerToQuatFast(euler, sk.rotationOrders[j]);
            }
            motion.appendFrame(t, r);
        }
        if (lex_.nextLine(lb, le)) {
            return fail("more frame rows than 'Frames: " + std::to_string(frameCount) + "' declares (found '" +
                        excerpt(std::string_view(lb, static_cast<std::size_t>(le - lb))) + "')");
        }
        if (lex_.tooLong()) return fail("line too long (binary data?)");
        if (opt_.ignoreForeignJointPositions) dropForeignPositions(motion);
        return motion;
    }

    // A joint's position channels are taken as world positions (and dropped)
    // when they sit far closer to where the joint is in the world than to its
    // local offset. Where both readings agree (a static parent at the origin,
    // as in the Bandai set) the channels are kept.
    static void dropForeignPositions(Motion& motion) {
        const Skeleton& sk = motion.skeleton();
        const auto jc = static_cast<std::size_t>(sk.jointCount());
        const auto frames = static_cast<std::size_t>(motion.frameCount());
        std::vector<std::size_t> candidates;
        for (std::size_t j = 1; j < jc; ++j)
            if (sk.hasPositionChannels(static_cast<int>(j))) candidates.push_back(j);
        if (candidates.empty() || frames == 0) return;
        auto& T = motion.allTranslations();
        auto& R = motion.allRotations();
        std::vector<std::size_t> chain;  // ancestors of j, root first
        for (std::size_t j : candidates) {
            chain.clear();
            for (int a = sk.parents[j]; a >= 0; a = sk.parents[static_cast<std::size_t>(a)])
                chain.push_back(static_cast<std::size_t>(a));
            std::reverse(chain.begin(), chain.end());
            double toOffset = 0, toWorld = 0;
            for (std::size_t f = 0; f < frames; ++f) {
                const glm::vec3* t = T.data() + f * jc;
                const glm::quat* r = R.data() + f * jc;
                // World transform of the parent, then of j placed by its offset.
                glm::vec3 pp(0);
                glm::quat pr(1, 0, 0, 0);
                for (std::size_t a : chain) {
                    pp = pp + pr * t[a];
                    pr = pr * r[a];
                }
                const glm::vec3 world = pp + pr * sk.offsets[j];
                toOffset += static_cast<double>(glm::length(t[j] - sk.offsets[j]));
                toWorld += static_cast<double>(glm::length(t[j] - world));
            }
            if (!(toWorld < 0.25 * toOffset)) continue;
            for (std::size_t f = 0; f < frames; ++f) T[f * jc + j] = sk.offsets[j];
            motion.source().warnings.push_back("joint '" + sk.names[j] +
                                               "': position channels hold world positions, not local ones; "
                                               "ignored, offset used");
        }
    }

    Lexer& lex_;
    std::string_view name_;
    std::size_t fileSize_;
    const BvhReadOptions& opt_;
    Skeleton sk_;
    std::unordered_set<std::string> names_;
    std::size_t totalChannels_ = 0;
    int depth_ = 0;
};

}  // namespace

Result<Motion> readBvhFromMemory(std::string_view data, std::string_view name, const BvhReadOptions& options) {
    Lexer lex(data);
    BvhParser parser(lex, name, data.size(), options);
    auto result = parser.run();
    if (result) {
        result->source().path = std::string(name);
        result->source().format = "bvh";
    }
    return result;
}

Result<Motion> readBvh(const std::filesystem::path& path, const BvhReadOptions& options) {
    const std::string name = path.filename().string();
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) return makeError(path.string() + ": is a directory, not a BVH file");
    std::FILE* f = std::fopen(path.string().c_str(), "rb");
    if (!f) return makeError(path.string() + ": cannot open (" + std::strerror(errno) + ")");
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> guard(f, &std::fclose);
    const auto size = std::filesystem::file_size(path, ec);
    Lexer lex(f);
    BvhParser parser(lex, name, ec ? 0 : static_cast<std::size_t>(size), options);
    auto result = parser.run();
    if (result) {
        result->source().path = path.string();
        result->source().format = "bvh";
    }
    return result;
}

}  // namespace fray
