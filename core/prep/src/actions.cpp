#include "fray/prep/actions.h"

#include <algorithm>

namespace fray::prep {
namespace {

std::size_t sz(int i) { return static_cast<std::size_t>(i); }

// Index of cut `frame` in doc.cuts, or -1.
int cutIndex(const MotionActions& doc, int frame) {
    const auto it = std::lower_bound(doc.cuts.begin(), doc.cuts.end(), frame);
    return it != doc.cuts.end() && *it == frame ? static_cast<int>(it - doc.cuts.begin()) : -1;
}

// Union of annotation lists, order kept.
void mergeInto(std::vector<std::string>& into, const std::vector<std::string>& from) {
    for (const auto& s : from) {
        if (std::find(into.begin(), into.end(), s) == into.end()) into.push_back(s);
    }
}

}  // namespace

bool ActionInfo::has(const std::string& annotation) const {
    return std::find(annotations.begin(), annotations.end(), annotation) != annotations.end();
}

MotionActions MotionActions::whole(int frameCount) {
    MotionActions doc;
    doc.frameCount = frameCount;
    doc.actions.resize(1);
    return doc;
}

int MotionActions::actionAt(int frame) const {
    return static_cast<int>(std::upper_bound(cuts.begin(), cuts.end(), frame) - cuts.begin());
}

std::optional<std::string> MotionActions::validate() const {
    if (frameCount < 1) return "frame count " + std::to_string(frameCount) + " must be positive";
    if (actions.size() != cuts.size() + 1) {
        return std::to_string(actions.size()) + " actions for " + std::to_string(cuts.size()) +
               " cuts (expected cuts + 1)";
    }
    int prev = 0;
    for (std::size_t i = 0; i < cuts.size(); ++i) {
        if (cuts[i] <= prev || cuts[i] >= frameCount) {
            return "cut " + std::to_string(i + 1) + " at frame " + std::to_string(cuts[i]) +
                   " must lie after " + std::to_string(prev) + " and before frame " + std::to_string(frameCount);
        }
        prev = cuts[i];
    }
    return std::nullopt;
}

Result<CutEdit> makeAddCut(const MotionActions& doc, int frame) {
    if (frame <= 0 || frame >= doc.frameCount) {
        return makeError("cannot cut at frame " + std::to_string(frame) + ": cuts lie in 1.." +
                         std::to_string(doc.frameCount - 1));
    }
    if (cutIndex(doc, frame) >= 0) return makeError("frame " + std::to_string(frame) + " is already a cut");
    CutEdit e;
    e.kind = CutEdit::Kind::Add;
    e.frame = frame;
    e.left = doc.actions[sz(doc.actionAt(frame))];
    e.right = e.left;
    return e;
}

Result<CutEdit> makeRemoveCut(const MotionActions& doc, int frame) {
    const int i = cutIndex(doc, frame);
    if (i < 0) return makeError("frame " + std::to_string(frame) + " is not a cut");
    CutEdit e;
    e.kind = CutEdit::Kind::Remove;
    e.frame = frame;
    e.left = doc.actions[sz(i)];
    e.right = doc.actions[sz(i + 1)];
    return e;
}

Result<CutEdit> makeMoveCut(const MotionActions& doc, int frame, int toFrame) {
    const int i = cutIndex(doc, frame);
    if (i < 0) return makeError("frame " + std::to_string(frame) + " is not a cut");
    const int lo = i == 0 ? 0 : doc.cuts[sz(i - 1)];
    const int hi = i + 1 < static_cast<int>(doc.cuts.size()) ? doc.cuts[sz(i + 1)] : doc.frameCount;
    if (toFrame <= lo || toFrame >= hi) {
        return makeError("cannot move the cut at frame " + std::to_string(frame) + " to " + std::to_string(toFrame) +
                         ": it must stay between frames " + std::to_string(lo + 1) + " and " +
                         std::to_string(hi - 1));
    }
    CutEdit e;
    e.kind = CutEdit::Kind::Move;
    e.frame = frame;
    e.toFrame = toFrame;
    return e;
}

Result<CutEdit> makeMergeActions(const MotionActions& doc, int action) {
    if (action < 0 || action + 1 >= doc.actionCount()) {
        return makeError("cannot merge action " + std::to_string(action) + " with the next: the motion has " +
                         std::to_string(doc.actionCount()) + " actions");
    }
    return makeRemoveCut(doc, doc.cuts[sz(action)]);
}

Status apply(MotionActions& doc, const CutEdit& edit) {
    switch (edit.kind) {
        case CutEdit::Kind::Add: {
            if (edit.frame <= 0 || edit.frame >= doc.frameCount || cutIndex(doc, edit.frame) >= 0) {
                return makeError("cannot add a cut at frame " + std::to_string(edit.frame));
            }
            const int a = doc.actionAt(edit.frame);
            doc.cuts.insert(doc.cuts.begin() + a, edit.frame);
            doc.actions[sz(a)] = edit.left;
            doc.actions.insert(doc.actions.begin() + a + 1, edit.right);
            return {};
        }
        case CutEdit::Kind::Remove: {
            const int i = cutIndex(doc, edit.frame);
            if (i < 0) return makeError("frame " + std::to_string(edit.frame) + " is not a cut");
            ActionInfo merged = edit.left;
            mergeInto(merged.annotations, edit.right.annotations);
            mergeInto(merged.proposed, edit.right.proposed);
            mergeInto(merged.joints, edit.right.joints);
            if (merged.name.empty()) merged.name = edit.right.name;
            doc.actions[sz(i)] = std::move(merged);
            doc.actions.erase(doc.actions.begin() + i + 1);
            doc.cuts.erase(doc.cuts.begin() + i);
            return {};
        }
        case CutEdit::Kind::Move: {
            auto checked = makeMoveCut(doc, edit.frame, edit.toFrame);
            if (!checked) return checked.error();
            doc.cuts[sz(cutIndex(doc, edit.frame))] = edit.toFrame;
            return {};
        }
    }
    return makeError("unknown cut edit");
}

CutEdit inverse(const CutEdit& edit) {
    CutEdit inv = edit;
    switch (edit.kind) {
        case CutEdit::Kind::Add:
            inv.kind = CutEdit::Kind::Remove;
            break;
        case CutEdit::Kind::Remove:
            inv.kind = CutEdit::Kind::Add;
            break;
        case CutEdit::Kind::Move:
            inv.frame = edit.toFrame;
            inv.toFrame = edit.frame;
            break;
    }
    return inv;
}

MotionActions recut(const MotionActions& doc, const std::vector<int>& cuts, int tolerance) {
    MotionActions out;
    out.frameCount = doc.frameCount;
    for (int c : cuts) {
        if (c > 0 && c < doc.frameCount && (out.cuts.empty() || c > out.cuts.back())) out.cuts.push_back(c);
    }
    out.actions.resize(out.cuts.size() + 1);
    for (int a = 0; a < out.actionCount(); ++a) {
        const int start = out.firstFrame(a);
        // The old action starting closest to this start, within tolerance.
        int best = -1, bestDist = tolerance + 1;
        for (int o = 0; o < doc.actionCount(); ++o) {
            const int d = std::abs(doc.firstFrame(o) - start);
            if (d < bestDist) bestDist = d, best = o;
        }
        if (best >= 0) out.actions[sz(a)] = doc.actions[sz(best)];
    }
    return out;
}

}  // namespace fray::prep
