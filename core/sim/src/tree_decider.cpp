#include "fray/sim/tree_decider.h"

#include <algorithm>
#include <cmath>

#include "planner_state.h"

namespace fray::sim {

using namespace planner;

struct TreeDecider::Impl {
    const ActionLibrary* lib = nullptr;
    SimOptions options;
    std::vector<CharacterSpec> specs;  // [0] decides, [1] the opponent model
    std::vector<float> combo;
    std::unique_ptr<detail::InteractionEngine> engine;
    Context ctx;
};

TreeDecider::TreeDecider() : impl_(std::make_unique<Impl>()) {}
TreeDecider::~TreeDecider() = default;

int TreeDecider::depth() const { return impl_->specs[0].depth; }

Result<std::unique_ptr<TreeDecider>> TreeDecider::make(const ActionLibrary& lib, const prep::ComboTable& combos, CharacterSpec self,
                                                        CharacterSpec opponent, SimOptions options) {
    for (const CharacterSpec* c : {&self, &opponent}) {
        if (c->allowed.empty()) return makeError("character '" + c->name + "' has no usable action");
        if (c->depth < 1) return makeError("character '" + c->name + "': depth must be at least 1");
        if (!std::is_sorted(c->allowed.begin(), c->allowed.end()) || !std::is_sorted(c->reactions.begin(), c->reactions.end())) {
            return makeError("character '" + c->name + "': allowed actions and reactions must be ascending");
        }
        for (int a : c->allowed) {
            if (a < 0 || a >= lib.size()) return makeError("character '" + c->name + "': action index " + std::to_string(a) + " is out of range");
        }
        for (int a : c->reactions) {
            if (a < 0 || a >= lib.size() || !lib.actions()[static_cast<std::size_t>(a)].is(kReactive)) {
                return makeError("character '" + c->name + "': reaction index " + std::to_string(a) + " is not a reactive action");
            }
        }
        if (c->weights.catches || c->weights.wPath > 0 || c->weights.wPsi > 0 || c->weights.wReq > 0) {
            return makeError("character '" + c->name + "': a tree-expansion duel decider takes competitive (boxing) weights only");
        }
    }
    if (self.side == opponent.side) return makeError("tree decider: the two characters must be on different sides");
    std::unique_ptr<TreeDecider> d(new TreeDecider());
    auto& m = *d->impl_;
    m.lib = &lib;
    m.options = options;
    self.opponent = -1, opponent.opponent = -1;
    self.group = opponent.group = 0;
    m.specs = {std::move(self), std::move(opponent)};
    m.combo = comboMatrix(lib, combos, m.specs);
    m.engine = std::make_unique<detail::InteractionEngine>(lib);
    m.ctx = baseContext(lib, m.options, m.combo, *m.engine);
    for (int i = 0; i < 2; ++i) {
        const auto& c = m.specs[static_cast<std::size_t>(i)];
        auto legal = legalChoices(lib, c);
        auto folded = foldVariants(lib, legal);
        m.ctx.members.push_back({i, &c, std::move(legal), std::move(folded), m.engine->addPool(c.reactions), makePathPlan(c)});
    }
    m.ctx.duel = true;
    m.ctx.boundedFrontier = true;
    return d;
}

Result<int> TreeDecider::decide(const DuelSideState& self, const DuelSideState& opponent, double t, TreeDecisionStats* out) const {
    const auto& m = *impl_;
    const auto& lib = *m.lib;
    GroupState g;
    g.time = t;
    g.n = 2;
    const DuelSideState* sides[2] = {&self, &opponent};
    for (std::size_t i = 0; i < 2; ++i) {
        const auto& in = *sides[i];
        if (in.action < 0 || in.action >= lib.size()) return makeError("tree decider: action index " + std::to_string(in.action) + " is out of range");
        if (!std::isfinite(in.start) || !std::isfinite(in.offset) || !std::isfinite(in.end)) return makeError("tree decider: a time is not finite");
        CharState& s = g.c[i];
        s.action = in.action;
        s.start = in.start;
        s.offset = in.offset;
        s.end = in.end;
        s.root = in.root;
        s.attackDone = in.attackDone;
        s.reacting = in.reacting;
        const std::size_t keep = std::min<std::size_t>(in.recent.size(), kRecent);
        for (std::size_t k = keep; k-- > 0;) {
            const int a = in.recent[k];
            if (a < 0 || a >= lib.size()) return makeError("tree decider: recent action index " + std::to_string(a) + " is out of range");
            pushRecent(m.ctx, s, a);
        }
    }
    // The decider's action ends now; the opponent's not before.
    if (!(g.c[1].end >= t)) return makeError("tree decider: the opponent's action ended before the decision (its decision is due first)");
    g.c[0].end = t;
    Stats st;
    st.budget = std::numeric_limits<std::int64_t>::max();
    bool fellBack = false;
    const int action = planner::decide(m.ctx, g, m.specs[0].depth, st, fellBack);
    if (out) {
        ++out->decisions;
        out->nodes += st.nodes, out->leaves += st.leaves, out->shallower += st.shallower;
        if (fellBack) ++out->fallbacks;
    }
    if (action < 0) return makeError("character '" + m.specs[0].name + "' has no action to take");
    return action;
}

}  // namespace fray::sim
