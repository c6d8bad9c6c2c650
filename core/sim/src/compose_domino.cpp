// Domino: falling bodies knock the next people over inside the painted area (SPEC 4.5).
#include "compose_grid.h"
#include "compose_kinds.h"
#include "fray/sim/compose/domino.h"

namespace fray::sim::detail {

namespace {

constexpr float kBystanderCell = 1.5f;    // m: one bystander at most per cell of the floor
constexpr double kBystanderJitter = 0.25;  // m: how far a bystander stands from its cell's centre

// Bystander cell b's own random stream: the scene's seed and b, mixed (splitmix64).
std::uint64_t bystanderSeed(std::uint64_t seed, int b) {
    auto mix = [](std::uint64_t z) {
        z += 0x9e3779b97f4a7c15ull;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    };
    return mix(seed ^ mix(0xb7u + static_cast<std::uint64_t>(b)));
}

struct DominoComposer : KindComposer<DominoSpec, DominoStats> {
    using KindComposer::KindComposer;

    // ---- domino: falling bodies knock the next people over, inside the painted area.
    struct Faller {
        int c = 0;
        double clipStart = 0;  // scene time of the clip's time 0
        int action = 0;
        RootXf root;           // placement of the clip's first frame
        double offset = 0;     // clip time the fall started at
        int patch = -1;        // the patch it fell in (as its character 2), -1: a start
    };

    // Stands character c in the guard from its first free moment until `until`,
    // the last guard timed so that its clip is at `clipTimeAtEnd` then.
    void standUntil(int c, const RootXf& at, double until, double clipTimeAtEnd) {
        const double lastStart = until - clipTimeAtEnd;
        auto holdAt = [&](double start, double end, double offset) {
            append(c, hold, start, at * lib.rootAt(hold, 0).inverse(), offset, end);
        };
        double t = track(c).empty() ? 0.0 : freeAt(c);
        while (t < lastStart - 1e-6) {
            const double end = std::min(lastStart, t + act(hold).duration);
            holdAt(t, end, 0.0);
            t = end;
        }
        if (until > t + 1e-9) holdAt(t, until, std::max(0.0, clipTimeAtEnd - (until - t)));
    }

    // Share of the painted floor within DominoStats::kCoverRadius of a spot.
    double coverage(const std::vector<glm::vec2>& fallers) const {
        constexpr float kStep = 0.25f;
        FloorGrid grid;
        for (std::size_t i = 0; i < fallers.size(); ++i) grid.insert(static_cast<int>(i), fallers[i]);
        const glm::vec2 lo = own.floor.extentMin(), hi = own.floor.extentMax();
        long painted = 0, covered = 0;
        for (float z = lo.y + 0.5f * kStep; z < hi.y; z += kStep) {
            for (float x = lo.x + 0.5f * kStep; x < hi.x; x += kStep) {
                const glm::vec2 q(x, z);
                if (!own.floor.paintedAt(q)) continue;
                ++painted;
                for (int i : grid.near(q, DominoStats::kCoverRadius)) {
                    if (glm::length(fallers[static_cast<std::size_t>(i)] - q) <= DominoStats::kCoverRadius) {
                        ++covered;
                        break;
                    }
                }
            }
        }
        return painted > 0 ? static_cast<double>(covered) / static_cast<double>(painted) : 0.0;
    }

    Status run(const ProgressFn& progress) {
        if (own.floor.empty()) return makeError("domino: no floor bitmap");
        if (own.starts.empty()) return makeError("domino: no start (where the first person falls)");
        std::vector<std::size_t> chainPatches;
        std::vector<char> isChain(patches.patches().size(), 0);
        for (std::size_t i = 0; i < patches.patches().size(); ++i) {
            const auto& p = patches.patches()[i];
            const auto& pattern = patches.patterns()[static_cast<std::size_t>(p.pattern)];
            if (!allowed[i] || pattern.entries.empty() || !isReactiveAnnotation(pattern.entries[0].annotation) ||
                pattern.entries[0].character != 0)
                continue;
            const bool pushes = std::any_of(p.hits.begin(), p.hits.end(), [](const HitEvent& h) { return h.attacker == 0 && !h.blocked; });
            if (pushes) chainPatches.push_back(i), isChain[i] = 1;
        }
        if (chainPatches.empty()) return makeError("domino: the patch library has no patch where a falling body knocks someone over (generate the fall-fall pattern)");
        std::vector<Print> prints;     // per character: where it stands and falls
        std::vector<glm::vec2> spots;  // per character: where it stands
        FloorGrid printGrid, spotGrid;  // the same, by where they are on the floor
        auto addPrint = [&](const Print& pr, const glm::vec2& spot) {
            printGrid.insert(static_cast<int>(prints.size()), pr.all);
            spotGrid.insert(static_cast<int>(spots.size()), spot);
            prints.push_back(pr);
            spots.push_back(spot);
        };
        // Does `print` overlap (by margin) the print of anyone but `except`?
        auto printClear = [&](const Print& print, int except, float margin) {
            const float grow = std::max(margin, 0.0f);
            for (int o : printGrid.near(SweptBox{print.all.lo - glm::vec2(grow), print.all.hi + glm::vec2(grow)})) {
                if (o != except && prints[static_cast<std::size_t>(o)].overlaps(print, margin)) return false;
            }
            return true;
        };
        std::vector<Faller> queue;
        auto byTime = [](const Faller& a, const Faller& b) { return a.clipStart > b.clipStart; };
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        for (std::size_t k = 0; k < own.starts.size(); ++k) {
            const auto& st = own.starts[k];
            if (!own.floor.paintedAt(st.pos)) {
                return makeError("domino: start " + std::to_string(k) + " at (" + std::to_string(st.pos.x) + ", " +
                                 std::to_string(st.pos.y) + ") is not on the painted area");
            }
            const Patch& p = patches.patches()[chainPatches[static_cast<std::size_t>(rng() % chainPatches.size())]];
            const int action = p.tracks[0].front().action;
            RootXf at;
            at.pos = st.pos;
            at.heading = wrapAngle(unit(rng) * 2 * std::numbers::pi);
            const int c = addCharacter("person-" + std::to_string(scene.characters.size() + 1), 0);
            standUntil(c, at, st.time, 0.0);
            const RootXf root = at * lib.rootAt(action, 0).inverse();
            append(c, action, st.time, root);
            Print first = footprint(p, 0, root * p.tracks[0].front().root.inverse());
            first.add(standingBox(at.pos));
            addPrint(first, at.pos);
            queue.push_back({c, st.time, action, root, 0.0, -1});
            std::push_heap(queue.begin(), queue.end(), byTime);
        }
        constexpr int kBranch = 3;
        while (!queue.empty() && static_cast<int>(scene.characters.size()) < own.maxCharacters) {
            std::pop_heap(queue.begin(), queue.end(), byTime);
            const Faller f = queue.back();
            queue.pop_back();
            // What the faller can knock over next: where it fell in a patch,
            // the chain patches spatially connected to it through the faller
            // (SPEC 4.3: it plays the same fall on, and the new victim never
            // meets whoever pushed it); a start, any chain patch that begins
            // with its fall. With the patch time from which the fall is the faller's.
            std::vector<std::pair<std::size_t, double>> next;
            if (f.patch >= 0) {
                for (const auto& l : patches.spatial()[static_cast<std::size_t>(f.patch)]) {
                    if (l.sharedA == 1 && l.sharedB == 0 && isChain[static_cast<std::size_t>(l.to)]) next.emplace_back(l.to, l.from);
                }
                std::sort(next.begin(), next.end());
            } else {
                for (std::size_t idx : chainPatches) {
                    if (patches.patches()[idx].tracks[0].front().action == f.action) next.emplace_back(idx, f.offset);
                }
            }
            // Where each of them would put its victim: what does not change
            // while this faller's victims are chosen (a footprint that
            // overlaps someone's goes on overlapping it as more are added).
            struct Candidate {
                std::size_t idx;
                glm::vec2 q;
                Print print;
            };
            std::vector<Candidate> candidates;
            if (static_cast<int>(scene.characters.size()) < own.maxCharacters) {
                for (const auto& [idx, from] : next) {
                    const Patch& p = patches.patches()[idx];
                    const HitEvent& hit = *std::find_if(p.hits.begin(), p.hits.end(), [](const HitEvent& h) { return h.attacker == 0; });
                    if (hit.time < from + 0.05) continue;  // the fall is already past that point
                    const RootXf xf = f.root * p.tracks[0].front().root.inverse();
                    const glm::vec2 q = (xf * p.tracks[1].front().placementAt(lib, 0)).pos;
                    if (!own.floor.paintedAt(q)) continue;
                    Print print = footprint(p, 1, xf);
                    print.add(standingBox(q));
                    candidates.push_back({idx, q, std::move(print)});
                }
            }
            std::vector<char> blocked(candidates.size(), 0);
            for (int child = 0; child < kBranch && static_cast<int>(scene.characters.size()) < own.maxCharacters; ++child) {
                int best = -1;
                double bestS = -std::numeric_limits<double>::max();
                for (std::size_t k = 0; k < candidates.size(); ++k) {
                    if (blocked[k]) continue;
                    const Candidate& cand = candidates[k];
                    // Boxes around bodies are generous: they must overlap by 0.15 m to count.
                    if (!printClear(cand.print, f.c, -0.15f)) {
                        blocked[k] = 1;
                        continue;
                    }
                    int near = 0;
                    for (int o : spotGrid.near(cand.q, 1.5f)) near += glm::length(spots[static_cast<std::size_t>(o)] - cand.q) < 1.5f ? 1 : 0;
                    const double sc = score(cand.idx, near, 0);
                    if (sc > bestS) bestS = sc, best = static_cast<int>(cand.idx);
                }
                if (best < 0) break;
                const Patch& p = patches.patches()[static_cast<std::size_t>(best)];
                const HitEvent hit = *std::find_if(p.hits.begin(), p.hits.end(), [](const HitEvent& h) { return h.attacker == 0; });
                const RootXf xf = f.root * p.tracks[0].front().root.inverse();
                const RootXf standing = xf * p.tracks[1].front().placementAt(lib, 0);
                const double tHit = f.clipStart + hit.time;
                const int n = addCharacter("person-" + std::to_string(scene.characters.size() + 1), 0);
                // It stands in the guard, at the clip time the patch had when the body hit it.
                const double holdTime = hit.time - p.tracks[1].front().start;
                standUntil(n, standing, tHit, holdTime);
                const auto& reaction = *std::find_if(p.tracks[1].begin(), p.tracks[1].end(), [](const ActionInstance& i) { return i.forced; });
                ActionInstance fall = reaction;
                fall.start = tHit;
                fall.end = tHit + (reaction.end - reaction.start);
                fall.root = xf * reaction.root;
                track(n).push_back(fall);
                HitEvent h = hit;
                h.time = tHit, h.attacker = f.c, h.defender = n, h.attackAction = f.action;
                scene.hits.push_back(h);
                Print print = footprint(p, 1, xf);
                print.add(standingBox(standing.pos));
                addPrint(print, standing.pos);
                used(static_cast<std::size_t>(best));
                ++ownStats.chainFalls;
                ownStats.spatialFalls += f.patch >= 0 ? 1 : 0;
                queue.push_back({n, tHit - reaction.offset, reaction.action, fall.root, reaction.offset, best});
                std::push_heap(queue.begin(), queue.end(), byTime);
            }
            if (!reportProgress(progress, std::min(1.0, static_cast<double>(scene.characters.size()) / own.maxCharacters), "compose")) {
                return cancelled();
            }
        }
        ownStats.paintedCoverage = coverage(spots);
        scene.floor = own.floor;  // the viewers draw the painted area
        // Bystanders outside the painted area, clear of every fall. The floor
        // is cut into cells of kBystanderCell; each cell has a spot jittered
        // inside it and a priority, both drawn from the seed and the cell
        // alone. The `background` cells of lowest priority among those whose
        // spots are clear of the painted area by the longest fall (of a chain
        // patch, from where its person stood, plus the boxes' margins) hold a
        // bystander each, named after the cell. So where a bystander stands
        // depends on the painting near it, not on how the chain went or on the
        // other bystanders: paint removes only the bystanders near the stroke
        // (and brings in others, in cells of next priority), and the others
        // keep their tracks (live re-plan, issue 23; docs/AUTHORING.md
        // "Affected characters"). Erasing may free a cell of lower priority
        // than a standing bystander's, who then gives way to it.
        float fallReach = 0;
        for (std::size_t idx : chainPatches) {
            const Patch& p = patches.patches()[idx];
            for (int role = 0; role < 2; ++role) {
                const glm::vec2 q = p.tracks[static_cast<std::size_t>(role)].front().placementAt(lib, 0).pos;
                for (const auto& box : footprint(p, role, RootXf{}).parts) {
                    const glm::vec2 far(std::max(std::fabs(box.lo.x - q.x), std::fabs(box.hi.x - q.x)),
                                        std::max(std::fabs(box.lo.y - q.y), std::fabs(box.hi.y - q.y)));
                    fallReach = std::max(fallReach, glm::length(far));
                }
            }
        }
        const float clearance = fallReach + 0.35f + 0.3f;  // the standing box and the margin kept from a fall
        ownStats.bystanderClearance = clearance;
        // The cells cover the bitmap and a band of the clearance round it, so
        // a painted area reaching the bitmap's edges still has people round it.
        const glm::vec2 lo = own.floor.extentMin() - glm::vec2(clearance), hi = own.floor.extentMax() + glm::vec2(clearance);
        struct Cell {
            std::uint64_t priority = 0;
            glm::vec2 q{0.0f};
            double heading = 0;
            bool free = false;  // clear of the painted area and of every fall
        };
        const int cols = std::max(0, static_cast<int>(std::floor((hi.x - lo.x) / kBystanderCell)));
        const int rows = std::max(0, static_cast<int>(std::floor((hi.y - lo.y) / kBystanderCell)));
        std::vector<Cell> cells(own.background > 0 ? static_cast<std::size_t>(cols) * static_cast<std::size_t>(rows) : 0u);
        std::vector<int> order;
        for (int id = 0; id < static_cast<int>(cells.size()); ++id) {
            Cell& cell = cells[static_cast<std::size_t>(id)];
            std::mt19937_64 cellRng(bystanderSeed(spec.seed, id));
            cell.priority = cellRng();
            // The jitter keeps two spots at least kBystanderCell - 2 kBystanderJitter apart.
            const float jx = static_cast<float>((2 * unit(cellRng) - 1) * kBystanderJitter);
            const float jz = static_cast<float>((2 * unit(cellRng) - 1) * kBystanderJitter);
            cell.q = lo + glm::vec2((static_cast<float>(id % cols) + 0.5f) * kBystanderCell + jx, (static_cast<float>(id / cols) + 0.5f) * kBystanderCell + jz);
            cell.heading = wrapAngle(unit(cellRng) * 2 * std::numbers::pi);
            Print box;
            box.add(standingBox(cell.q));
            // printClear is a safeguard: the clearance keeps every fall away already.
            cell.free = !own.floor.paintedWithin(cell.q, clearance) && printClear(box, -1, 0.3f);
            order.push_back(id);
        }
        std::sort(order.begin(), order.end(), [&](int x, int y) {
            const auto px = cells[static_cast<std::size_t>(x)].priority, py = cells[static_cast<std::size_t>(y)].priority;
            return px != py ? px < py : x < y;
        });
        for (int id : order) {
            if (ownStats.bystanders >= own.background) break;
            const Cell& cell = cells[static_cast<std::size_t>(id)];
            if (!cell.free) continue;  // a fall could reach it: no one stands there
            RootXf place;
            place.pos = cell.q;
            place.heading = cell.heading;
            const int c = addCharacter("bystander-" + std::to_string(id + 1), 1);
            append(c, hold, 0.0, place * lib.rootAt(hold, 0).inverse());
            Print box;
            box.add(standingBox(cell.q));
            addPrint(box, cell.q);
            ++ownStats.bystanders;
        }
        // Everyone still standing stays until the last one has fallen, or to
        // the spec's duration when it gives one and that is later (a setup
        // gives one, so that bystanders' tracks do not depend on the chain).
        double end = spec.durationGiven ? spec.duration : 0.0;
        for (int c = 0; c < static_cast<int>(scene.characters.size()); ++c) end = std::max(end, freeAt(c));
        for (int c = 0; c < static_cast<int>(scene.characters.size()); ++c) {
            if (!act(track(c).back().action).is(kReactive)) waitUntil(c, end);
        }
        return {};
    }
};

Status parseDomino(const prep::JsonReader& rd, const Json& j, DominoSpec& s) {
    if (auto f = rd.field(j, "", "floor", false); !f) return f.error();
    else if (*f) {
        const Json& fl = **f;
        if (!fl.is_object()) return rd.error("/floor", "must be an object {bitmap, metres_per_pixel, origin}");
        FRAY_TRY(file, rd.stringAt(fl, "/floor", "bitmap"));
        if (file.empty()) return rd.error("/floor/bitmap", "must name a PNG file");
        s.floorFile = file;
        if (auto m = rd.field(fl, "/floor", "metres_per_pixel", false); !m) return m.error();
        else if (*m) {
            FRAY_TRY(x, rd.number(**m, "/floor/metres_per_pixel"));
            if (!(x > 0.001) || x > 10) return rd.error("/floor/metres_per_pixel", "must be in (0.001, 10]");
            s.metresPerPixel = x;
        }
        if (auto o = rd.field(fl, "/floor", "origin", false); !o) return o.error();
        else if (*o) {
            if (!(*o)->is_array() || (*o)->size() != 2) return rd.error("/floor/origin", "must be [x, z]");
            FRAY_TRY(x, rd.number((**o)[0], "/floor/origin/0"));
            FRAY_TRY(z, rd.number((**o)[1], "/floor/origin/1"));
            if (std::fabs(x) > 1e4 || std::fabs(z) > 1e4) return rd.error("/floor/origin", "is too far out");
            s.floorOrigin = glm::vec2(static_cast<float>(x), static_cast<float>(z));
        }
    }
    if (auto f = rd.field(j, "", "starts", false); !f) return f.error();
    else if (*f) {
        if (!(*f)->is_array()) return rd.error("/starts", "must be an array of {time, x, z}");
        for (std::size_t i = 0; i < (*f)->size(); ++i) {
            const std::string p = "/starts/" + std::to_string(i);
            const Json& st = (**f)[i];
            if (!st.is_object()) return rd.error(p, "must be an object {time, x, z}");
            FRAY_TRY(t, rd.numberAt(st, p, "time"));
            FRAY_TRY(x, rd.numberAt(st, p, "x"));
            FRAY_TRY(z, rd.numberAt(st, p, "z"));
            if (t < 0 || t > 3600) return rd.error(p + "/time", "must be in [0, 3600] seconds");
            if (std::fabs(x) > 1e4 || std::fabs(z) > 1e4) return rd.error(p, "is too far out");
            s.starts.push_back({t, glm::vec2(static_cast<float>(x), static_cast<float>(z))});
        }
    }
    if (auto st = optionalInt(rd, j, "background", 0, 10000, s.background); !st) return st.error();
    return optionalInt(rd, j, "max_characters", 1, 100000, s.maxCharacters);
}

Status checkDomino(const prep::JsonReader& rd, const DominoSpec& s) {
    if (s.floorFile.empty()) return rd.error("/floor", "a domino scene needs a floor bitmap (the painted area where people fall)");
    if (s.starts.empty()) return rd.error("/starts", "a domino scene needs at least one start (where the first person falls)");
    return {};
}

constexpr const char* kFields[] = {"floor", "starts", "background", "max_characters"};

}  // namespace

const SceneKindModule& dominoKind() {
    static const SceneKindModule kind = kindModule<DominoComposer, DominoSpec, parseDomino, checkDomino>(true, kFields);
    return kind;
}

}  // namespace fray::sim::detail
