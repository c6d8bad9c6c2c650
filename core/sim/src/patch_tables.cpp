// Connection tables and standard poses (SPEC 4.3, 4.4). Which links they hold
// is the link rule: bump kPatchLinkRule (patches.h) whenever it changes; the
// library file (patch_file.cpp) stores them.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <unordered_map>
#include <vector>

#include <tbb/parallel_for.h>

#include "fray/sim/patches.h"
#include "interaction.h"
#include "patch_library_builder.h"

namespace fray::sim {

namespace {

constexpr double kContinueF = 0.5;    // F below which a final configuration continues into an initial one
constexpr double kConfigR = 0.30;     // m: C_r of F (configDistance)
constexpr double kStandardF = 0.35;   // clusters grow until every configuration is this close to its pose
constexpr int kMaxStandardPoses = 64;
constexpr float kClearance = 0.15f;   // m between the bounding boxes of characters that must not meet
constexpr int kSamplesPerSlice = 8;   // body tests per swept slice where the boxes come near (30 Hz over 0.25 s)
constexpr float kBodyShrink = 0.82f;  // as the composer's penetration test
constexpr float kPelvisReach = 1.2f;  // bodies whose pelvises are further apart never touch (coreBodiesOverlap's default)

PatchConfig swapped(const PatchConfig& c) { return {c.r, c.theta2, c.theta1, c.delay}; }

bool continues(const ActionLibrary& lib, int from, int to) { return lib.continuesInto(from, to); }

// Does character `who` of b, placed by xf, ever come near `box`?
bool sweptMeets(const Patch& b, int who, const RootXf& xf, const SweptBox& box) {
    for (const auto& s : b.swept[static_cast<std::size_t>(who)]) {
        if (placedBox(s, xf).overlaps(box, kClearance)) return true;
    }
    return false;
}

// Whether each patch's last actions continue into each patch's first ones,
// asked once per pair of distinct actions (a library has a few hundred of
// each, against millions of patch pairs).
class ContinuationTable {
public:
    ContinuationTable(const ActionLibrary& lib, const std::vector<Patch>& patches) {
        std::vector<int> lastIndex(static_cast<std::size_t>(lib.size()), -1), firstIndex(lastIndex);
        std::vector<int> lasts, firsts;
        auto index = [](std::vector<int>& at, std::vector<int>& list, int action) {
            auto& i = at[static_cast<std::size_t>(action)];
            if (i < 0) i = static_cast<int>(list.size()), list.push_back(action);
            return i;
        };
        last_.resize(patches.size()), first_.resize(patches.size());
        for (std::size_t p = 0; p < patches.size(); ++p) {
            for (std::size_t k = 0; k < 2; ++k) {
                last_[p][k] = index(lastIndex, lasts, patches[p].tracks[k].back().action);
                first_[p][k] = index(firstIndex, firsts, patches[p].tracks[k].front().action);
            }
        }
        firstCount_ = firsts.size();
        cont_.resize(lasts.size() * firsts.size());
        for (std::size_t i = 0; i < lasts.size(); ++i)
            for (std::size_t j = 0; j < firsts.size(); ++j) cont_[i * firstCount_ + j] = continues(lib, lasts[i], firsts[j]);
    }
    // Does patch a's character ka's last action continue into patch b's character kb's first one?
    bool operator()(std::size_t a, int ka, std::size_t b, int kb) const {
        const auto i = static_cast<std::size_t>(last_[a][static_cast<std::size_t>(ka)]);
        const auto j = static_cast<std::size_t>(first_[b][static_cast<std::size_t>(kb)]);
        return cont_[i * firstCount_ + j] != 0;
    }

private:
    std::vector<std::array<int, 2>> last_, first_;  // per patch and character: dense action index
    std::size_t firstCount_ = 0;
    std::vector<std::uint8_t> cont_;
};

void temporalTable(const ActionLibrary& lib, PatchLibrary::Data& out) {
    const auto n = out.patches.size();
    out.temporal.assign(n, {});
    const ContinuationTable continuesTo(lib, out.patches);
    // Per patch and character: where its last action ends, the inverse of
    // where its first one starts, and the hull of its swept boxes (a joiner
    // whose placed hull stays clear of the leaving one meets it nowhere).
    struct Ends {
        std::array<RootXf, 2> end, startInverse;
        std::array<SweptBox, 2> hull{SweptBox::empty(), SweptBox::empty()};
    };
    std::vector<Ends> ends(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Patch& p = out.patches[i];
        for (std::size_t k = 0; k < 2; ++k) {
            ends[i].end[k] = p.endPlacement(lib, static_cast<int>(k));
            ends[i].startInverse[k] = p.tracks[k].front().root.inverse();
            for (const auto& box : p.swept[k]) ends[i].hull[k].add(box);
        }
    }
    constexpr float kHullSlack = 1e-3f;  // m: rounding of the placed hull against the placed slices
    // Each patch's row on its own: the same table with one thread or many.
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t ia) {
        const Patch& a = out.patches[ia];
        for (std::size_t ib = 0; ib < n; ++ib) {
            const Patch& b = out.patches[ib];
            for (int roles = 0; roles < 2; ++roles) {
                // b's character m is a's character (roles ? 1 - m : m).
                const int m0 = roles ? 1 : 0;  // b's character that a's character 0 becomes
                const std::array<bool, 2> cont = {continuesTo(ia, 0, ib, m0), continuesTo(ia, 1, ib, 1 - m0)};
                if (!cont[0] && !cont[1]) continue;
                const PatchConfig fin = roles ? swapped(a.final) : a.final;
                // F is at least its distance term: most pairs are rejected by it alone.
                const double dr = (fin.r - b.initial.r) / kConfigR;
                if (cont[0] && cont[1] && dr * dr <= kContinueF && configDistance(fin, b.initial) <= kContinueF) {
                    out.temporal[ia].push_back({static_cast<int>(ib), static_cast<std::int8_t>(roles), -1});
                    continue;
                }
                // One continues, the other leaves and b's other character joins:
                // the leaving one (standing where a leaves it) must not meet the joiner.
                for (int k = 0; k < 2; ++k) {
                    if (!cont[static_cast<std::size_t>(k)]) continue;
                    const int m = k == 0 ? m0 : 1 - m0;
                    const RootXf xf = ends[ia].end[static_cast<std::size_t>(k)] * ends[ib].startInverse[static_cast<std::size_t>(m)];
                    const SweptBox leaving = a.swept[static_cast<std::size_t>(1 - k)].back();
                    const bool hullMeets = placedBox(ends[ib].hull[static_cast<std::size_t>(1 - m)], xf).overlaps(leaving, kClearance + kHullSlack);
                    if (hullMeets && sweptMeets(b, 1 - m, xf, leaving)) continue;
                    out.temporal[ia].push_back({static_cast<int>(ib), static_cast<std::int8_t>(roles), static_cast<std::int8_t>(k)});
                    break;
                }
            }
        }
    });
}

// The body of a patch's character at patch time t (held before its first
// action and after its last), placed by xf.
detail::BodyPose bodyIn(const Patch& p, int who, double t, const RootXf& xf) {
    const auto& track = p.tracks[static_cast<std::size_t>(who)];
    const auto& inst = track[static_cast<std::size_t>(std::max(0, instanceIndexAt(track, t)))];
    return {inst.action, inst.clipTimeAt(t), xf * inst.root};
}

void spatialTable(const ActionLibrary& lib, PatchLibrary::Data& out) {
    const auto n = out.patches.size();
    out.spatial.assign(n, {});
    // Index: first action of each character of every patch.
    std::unordered_map<int, std::vector<std::pair<int, int>>> heads;  // action -> (patch, character)
    for (std::size_t ib = 0; ib < n; ++ib) {
        for (int m = 0; m < 2; ++m) heads[out.patches[ib].tracks[static_cast<std::size_t>(m)].front().action].push_back({static_cast<int>(ib), m});
    }
    // Each patch's links on their own (in parallel; the same table every time).
    tbb::parallel_for(std::size_t{0}, n, [&](std::size_t ia) {
        const Patch& a = out.patches[ia];
        for (int k = 0; k < 2; ++k) {
            const auto& ta = a.tracks[static_cast<std::size_t>(k)];
            for (std::size_t j = 0; j < ta.size(); ++j) {
                const auto it = heads.find(ta[j].action);
                if (it == heads.end()) continue;
                // a's unshared body at the sample times of a link, made once
                // per offset (the links of one shared action mostly share it).
                double bodiesAt = std::numeric_limits<double>::quiet_NaN();
                std::vector<std::optional<detail::CoreBody>> bodies;
                auto bodyOfA = [&](double offset, std::size_t sample, double t) -> const detail::CoreBody& {
                    if (!(offset == bodiesAt)) bodies.clear(), bodiesAt = offset;
                    if (bodies.size() <= sample) bodies.resize(sample + 1);
                    if (!bodies[sample]) bodies[sample].emplace(lib, bodyIn(a, 1 - k, t, RootXf{}), kBodyShrink);
                    return *bodies[sample];
                };
                for (const auto& [ibi, m] : it->second) {
                    if (static_cast<std::size_t>(ibi) == ia) continue;
                    const Patch& b = out.patches[static_cast<std::size_t>(ibi)];
                    const auto& tb = b.tracks[static_cast<std::size_t>(m)];
                    // The shared character's series: a's tail from j equals b's
                    // head (or contains it). Its first action may be a forced
                    // reaction in a and b's own first entry (a victim's fall
                    // that knocks the next one over), and a may join that clip
                    // later (from the reaction's best-matching frame, which b
                    // plays from further back): clip times line up, and where
                    // either goes on to another action the other must not
                    // still be in the clip.
                    const auto& x0 = ta[j];
                    const auto& y0 = tb.front();
                    const double xEnd = x0.offset + (x0.end - x0.start), yEnd = y0.offset + (y0.end - y0.start);
                    const bool xMore = j + 1 < ta.size(), yMore = tb.size() > 1;
                    bool same = y0.offset <= x0.offset + 1e-6 && (!xMore || yEnd <= xEnd + 1e-6) && (!yMore || xEnd <= yEnd + 1e-6);
                    for (std::size_t q = 1; q < tb.size() && j + q < ta.size() && same; ++q) {
                        const auto& x = ta[j + q];
                        const auto& y = tb[q];
                        same = x.action == y.action && std::fabs(x.offset - y.offset) < 1e-6 &&
                               std::fabs((x.end - x.start) - (y.end - y.start)) < 1e-6 && x.forced == y.forced;
                    }
                    if (!same) continue;
                    const double offset = (x0.start - x0.offset) - (y0.start - y0.offset);
                    const double from = y0.start + (x0.offset - y0.offset);
                    const RootXf xf = ta[j].root * tb.front().root.inverse();
                    // The unshared characters never meet while both exist:
                    // their swept boxes stay apart. Where a reaction goes on as
                    // b's first entry (a faller pushing the next one, whose
                    // victims stand close by on purpose), where the boxes come
                    // near, their bodies must not touch instead (the composer's
                    // test, every 1/32 s). Testing bodies for every link would
                    // cost a 6,000-patch library four times its generation.
                    const bool testBodies = x0.forced != y0.forced || std::fabs(x0.offset - y0.offset) > 1e-6;
                    const auto& sa = a.swept[static_cast<std::size_t>(1 - k)];
                    const auto& sb = b.swept[static_cast<std::size_t>(1 - m)];
                    bool meet = false;
                    for (std::size_t q = 0; q < sb.size() && !meet; ++q) {
                        const double t = offset + static_cast<double>(q) * kSweptSlice;
                        const auto slice = static_cast<std::size_t>(std::max(0.0, std::floor(t / kSweptSlice)));
                        const SweptBox other = slice < sa.size() ? sa[slice] : sa.back();
                        if (!placedBox(sb[q], xf).overlaps(other, kClearance)) continue;
                        meet = !testBodies;
                        for (int s = 0; s < kSamplesPerSlice && !meet; ++s) {
                            const double at = (static_cast<double>(q) + static_cast<double>(s) / kSamplesPerSlice) * kSweptSlice;
                            const detail::CoreBody mine(lib, bodyIn(b, 1 - m, at, xf), kBodyShrink);
                            meet = detail::coreBodiesOverlap(bodyOfA(offset, q * kSamplesPerSlice + static_cast<std::size_t>(s), offset + at), mine, kPelvisReach);
                        }
                    }
                    if (meet) continue;
                    out.spatial[ia].push_back(
                        {ibi, static_cast<std::int8_t>(k), static_cast<std::int8_t>(m), static_cast<float>(offset), static_cast<float>(from)});
                }
            }
        }
    });
}

PatchConfig meanConfig(const std::vector<const PatchConfig*>& members) {
    PatchConfig c;
    double s1 = 0, c1 = 0, s2 = 0, c2 = 0;
    for (const auto* m : members) {
        c.r += m->r;
        s1 += std::sin(m->theta1), c1 += std::cos(m->theta1);
        s2 += std::sin(m->theta2), c2 += std::cos(m->theta2);
    }
    c.r /= static_cast<double>(members.size());
    c.theta1 = std::atan2(s1, c1);
    c.theta2 = std::atan2(s2, c2);
    return c;
}

// K-means under F, K grown (farthest point first) until every configuration
// is within kStandardF of its pose.
void standardPoses(PatchLibrary& lib) {
    PatchLibrary::Data& out = detail::built(lib);
    std::vector<PatchConfig> configs;
    for (const auto& p : out.patches) configs.push_back(p.initial), configs.push_back(p.final);
    out.standardPoses.clear();
    if (configs.empty()) return;
    std::vector<PatchConfig> centres = {configs.front()};
    std::vector<int> label(configs.size(), 0);
    for (;;) {
        for (int iter = 0; iter < 12; ++iter) {
            for (std::size_t i = 0; i < configs.size(); ++i) {
                double best = std::numeric_limits<double>::max();
                for (std::size_t k = 0; k < centres.size(); ++k) {
                    const double d = configDistance(configs[i], centres[k]);
                    if (d < best) best = d, label[i] = static_cast<int>(k);
                }
            }
            for (std::size_t k = 0; k < centres.size(); ++k) {
                std::vector<const PatchConfig*> members;
                for (std::size_t i = 0; i < configs.size(); ++i) {
                    if (label[i] == static_cast<int>(k)) members.push_back(&configs[i]);
                }
                if (!members.empty()) centres[k] = meanConfig(members);
            }
        }
        double worst = -1;
        std::size_t worstI = 0;
        for (std::size_t i = 0; i < configs.size(); ++i) {
            const double d = configDistance(configs[i], centres[static_cast<std::size_t>(label[i])]);
            if (d > worst) worst = d, worstI = i;
        }
        if (worst <= kStandardF || static_cast<int>(centres.size()) >= kMaxStandardPoses) break;
        centres.push_back(configs[worstI]);
    }
    out.standardPoses = centres;
    out.initialPose.assign(out.patches.size(), 0);
    out.finalPose.assign(out.patches.size(), 0);
    for (std::size_t i = 0; i < out.patches.size(); ++i) {
        out.initialPose[i] = lib.nearestPose(out.patches[i].initial);
        out.finalPose[i] = lib.nearestPose(out.patches[i].final);
    }
}

}  // namespace

void buildConnections(const ActionLibrary& lib, PatchLibrary& out) {
    temporalTable(lib, detail::built(out));
    spatialTable(lib, detail::built(out));
    standardPoses(out);
}

}  // namespace fray::sim
