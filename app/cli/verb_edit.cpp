// Headless counterparts of the editor's action edits (issue 22 item 5):
// `annotate` (an action's description) and `cuts` (a motion's cuts). Both drive
// an authoring::ProjectDocument, so the CLI checks edits by the editor's rules.
// The edits of one invocation run in command-line order; the project is saved
// once, atomically, only when every edit succeeded.
#include <QString>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "fray/authoring/project_document.h"
#include "verbs.h"

namespace fray::cli {
namespace {

using authoring::ProjectDocument;

std::string quoted(const std::string& s) {
    return "\"" + s + "\"";
}

Result<int> parseInt(const std::string& text, const std::string& what) {
    int value = 0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value);
    if (text.empty() || ec != std::errc() || ptr != end) {
        return makeError(what + ": expected a whole number, got '" + text + "'");
    }
    return value;
}

Result<double> parseNumber(const std::string& text, const std::string& what) {
    double value = 0;
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value);
    if (text.empty() || ec != std::errc() || ptr != end) {
        return makeError(what + ": expected a number, got '" + text + "'");
    }
    if (!std::isfinite(value)) return makeError(what + ": " + text + " is not a finite number");
    return value;
}

// "MIN:MAX" with finite numbers and MIN <= MAX.
Result<std::pair<double, double>> parseRange(const std::string& text, const std::string& flag) {
    const auto colon = text.find(':');
    if (colon == std::string::npos) return makeError(flag + ": expected MIN:MAX, got '" + text + "'");
    auto lo = parseNumber(text.substr(0, colon), flag + " MIN");
    if (!lo) return lo.error();
    auto hi = parseNumber(text.substr(colon + 1), flag + " MAX");
    if (!hi) return hi.error();
    if (*hi < *lo)
        return makeError(flag + ": MAX " + text.substr(colon + 1) + " is below MIN " + text.substr(0, colon));
    return std::pair{*lo, *hi};
}

// ACTION is an index, or the name of exactly one action of the motion. The
// annotate edits keep the number of actions, so the index stays valid.
Result<int> resolveAction(const prep::ProjectMotion& m, const std::string& spec) {
    if (!spec.empty() && spec.find_first_not_of("0123456789") == std::string::npos) {
        auto index = parseInt(spec, "ACTION");
        if (!index) return index.error();
        if (*index >= m.actions.actionCount()) {
            return makeError("motion " + quoted(m.id) + ", action " + spec +
                             ": no such action (the motion has " + std::to_string(m.actions.actionCount()) +
                             ")");
        }
        return index;
    }
    std::vector<int> hits;
    for (int i = 0; i < m.actions.actionCount(); ++i) {
        if (m.actions.actions[static_cast<std::size_t>(i)].name == spec) hits.push_back(i);
    }
    if (hits.empty()) return makeError("motion " + quoted(m.id) + ": no action is named " + quoted(spec));
    if (hits.size() > 1) {
        std::string list;
        for (int i : hits)
            list += (list.empty() ? "" : ", ") + std::to_string(i);
        return makeError("motion " + quoted(m.id) + ": " + std::to_string(hits.size()) +
                         " actions are named " + quoted(spec) + " (" + list + "): give the index");
    }
    return hits.front();
}

// Opens the project and checks the motion; the error is ready for fail().
Result<std::unique_ptr<ProjectDocument>> openFor(const std::string& project, const std::string& motionId) {
    auto doc = ProjectDocument::open(project);
    if (!doc) return doc.error();
    if (!(*doc)->project().findMotion(motionId)) {
        return makeError(project + ": the project has no motion " + quoted(motionId));
    }
    return std::move(*doc);
}

// The command texts of the undo stack, in order.
std::string commandTexts(const ProjectDocument& doc) {
    std::string out;
    const QUndoStack* stack = doc.undoStack();
    for (int i = 0; i < stack->count(); ++i)
        out += (out.empty() ? "" : "; ") + stack->text(i).toStdString();
    return out;
}

// Saves when something changed; prints "<project>: <where>: <commands>".
void saveAndReport(ProjectDocument& doc, const std::string& project, const std::string& where,
                   const std::string& after = {}) {
    if (doc.undoStack()->count() == 0) {
        std::printf("%s: %s: nothing changed\n", project.c_str(), where.c_str());
        return;
    }
    // app/cli has no helper yet for editing a project under an advisory lock:
    // save() writes atomically (temporary file, rename), so a failed save keeps the old file.
    if (auto st = doc.save(); !st) return fail(st.error().message);
    std::printf("%s: %s: %s%s\n", project.c_str(), where.c_str(), commandTexts(doc).c_str(), after.c_str());
}

// ---- annotate ---------------------------------------------------------------
struct AnnotateArgs {
    std::string project, motion, action;
    CLI::App* cmd = nullptr;
};

// The range flags, gathered from the whole command line into one edit.
struct Ranges {
    std::optional<std::pair<double, double>> distance, angle, facing, timing;
};

struct Edit {
    std::string flag;
    std::function<Status(ProjectDocument&)> run;
};

std::vector<std::string> splitJoints(const std::string& text) {
    std::vector<std::string> joints;
    if (text.empty()) return joints;  // --joints '' clears them
    std::size_t start = 0;
    while (true) {
        const auto comma = text.find(',', start);
        std::string joint = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        // "LeftHand, RightHand": spaces around a name are not part of it.
        joint.erase(0, joint.find_first_not_of(' '));
        joint.erase(joint.find_last_not_of(' ') + 1);
        joints.push_back(std::move(joint));
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return joints;
}

const prep::ActionInfo& actionInfo(const ProjectDocument& d, const std::string& motion, int action) {
    return d.project().findMotion(motion)->actions.actions[static_cast<std::size_t>(action)];
}

// Every range flag of the command line, as one edit of the initial conditions.
Status setRanges(ProjectDocument& d, const std::string& motion, int action, const Ranges& r) {
    auto c = actionInfo(d, motion, action).initialConditions;
    if (!c) {
        if (!r.distance || !r.angle || !r.facing || !r.timing) {
            return makeError("motion " + quoted(motion) + ", action " + std::to_string(action) +
                             " has no initial-condition ranges yet: give --distance, --angle, --facing and "
                             "--timing together");
        }
        c = prep::InitialConditions{};
    }
    if (r.distance) std::tie(c->minDistance, c->maxDistance) = *r.distance;
    if (r.angle) std::tie(c->minAngle, c->maxAngle) = *r.angle;
    if (r.facing) std::tie(c->minFacing, c->maxFacing) = *r.facing;
    if (r.timing) std::tie(c->minTiming, c->maxTiming) = *r.timing;
    return d.setInitialConditions(motion, action, c);
}

// Confirms or rejects the proposals the action has when this runs, one command each.
Status settleProposals(ProjectDocument& d, const std::string& motion, int action, bool confirm) {
    const auto words = actionInfo(d, motion, action).proposed;
    for (const auto& w : words) {
        Status st = confirm ? d.confirmProposal(motion, action, w) : d.rejectProposal(motion, action, w);
        if (!st) return st;
    }
    return {};
}

void runAnnotate(const AnnotateArgs& a) {
    auto opened = openFor(a.project, a.motion);
    if (!opened) return fail(opened.error().message);
    ProjectDocument& doc = **opened;
    auto index = resolveAction(*doc.project().findMotion(a.motion), a.action);
    if (!index) return fail(a.project + ": " + index.error().message);
    const std::string motion = a.motion;
    const int action = *index;

    // One edit per flag occurrence, in command-line order.
    std::vector<Edit> edits;
    auto ranges = std::make_shared<Ranges>();
    bool rangesQueued = false;
    std::map<const CLI::Option*, std::size_t> used;  // values taken so far, per option
    for (const CLI::Option* opt : a.cmd->parse_order()) {
        if (opt->get_positional()) continue;
        const std::string flag = opt->get_name();
        const auto& results = opt->results();
        const std::size_t n = used[opt]++;
        const std::string value = n < results.size() ? results[n] : std::string();
        const auto push = [&](std::function<Status(ProjectDocument&)> run) { edits.push_back({flag, std::move(run)}); };
        if (flag == "--name") {
            push([=](ProjectDocument& d) { return d.setActionName(motion, action, value); });
        } else if (flag == "--add") {
            push([=](ProjectDocument& d) { return d.addAnnotation(motion, action, value); });
        } else if (flag == "--remove") {
            push([=](ProjectDocument& d) { return d.removeAnnotation(motion, action, value); });
        } else if (flag == "--confirm") {
            push([=](ProjectDocument& d) { return d.confirmProposal(motion, action, value); });
        } else if (flag == "--reject") {
            push([=](ProjectDocument& d) { return d.rejectProposal(motion, action, value); });
        } else if (flag == "--confirm-all" || flag == "--reject-all") {
            const bool confirm = flag == "--confirm-all";
            push([=](ProjectDocument& d) { return settleProposals(d, motion, action, confirm); });
        } else if (flag == "--joints") {
            push([=](ProjectDocument& d) { return d.setJoints(motion, action, splitJoints(value)); });
        } else if (flag == "--direction") {
            push([=](ProjectDocument& d) { return d.setAttackDirection(motion, action, value); });
        } else if (flag == "--no-direction") {
            push([=](ProjectDocument& d) { return d.setAttackDirection(motion, action, std::nullopt); });
        } else if (flag == "--defended") {
            push([=](ProjectDocument& d) { return d.setDefendedPart(motion, action, value); });
        } else if (flag == "--no-defended") {
            push([=](ProjectDocument& d) { return d.setDefendedPart(motion, action, std::nullopt); });
        } else if (flag == "--no-ranges") {
            push([=](ProjectDocument& d) { return d.setInitialConditions(motion, action, std::nullopt); });
        } else if (flag == "--distance" || flag == "--angle" || flag == "--facing" || flag == "--timing") {
            auto range = parseRange(value, flag);
            if (!range) return fail(a.project + ": " + range.error().message);
            // Degrees on the command line, radians in the project.
            if (flag == "--angle" || flag == "--facing") {
                range->first *= std::numbers::pi / 180.0;
                range->second *= std::numbers::pi / 180.0;
            }
            (flag == "--distance" ? ranges->distance
             : flag == "--angle"  ? ranges->angle
             : flag == "--facing" ? ranges->facing
                                  : ranges->timing) = *range;
            // One edit, where the first range flag stands, with every range flag given.
            if (!rangesQueued) push([=](ProjectDocument& d) { return setRanges(d, motion, action, *ranges); });
            rangesQueued = true;
        }
    }
    if (edits.empty()) return fail("annotate: give at least one edit (see fray-cli annotate --help)");

    for (const auto& e : edits) {
        if (auto st = e.run(doc); !st) return fail(a.project + ": " + e.flag + ": " + st.error().message);
    }
    std::string where = "motion " + quoted(motion) + ", action " + std::to_string(action);
    if (const std::string& name = actionInfo(doc, motion, action).name; !name.empty()) where += " (" + name + ")";
    saveAndReport(doc, a.project, where);
}

// ---- cuts -------------------------------------------------------------------
struct CutsArgs {
    std::string project, motion, op;
    std::vector<std::string> args;
    bool json = false;
};

void listCuts(const prep::ProjectMotion& m, bool json) {
    const auto& doc = m.actions;
    if (json) {
        nlohmann::ordered_json out;
        out["motion"] = m.id;
        out["frame_count"] = doc.frameCount;
        out["cuts"] = doc.cuts;
        out["actions"] = nlohmann::ordered_json::array();
        for (int i = 0; i < doc.actionCount(); ++i) {
            out["actions"].push_back({{"index", i},
                                      {"first_frame", doc.firstFrame(i)},
                                      {"last_frame", doc.lastFrame(i)},
                                      {"name", doc.actions[static_cast<std::size_t>(i)].name}});
        }
        std::printf("%s\n", out.dump(2).c_str());
        return;
    }
    std::printf("motion \"%s\": %d frames, %zu cuts, %d actions\n", m.id.c_str(), doc.frameCount,
                doc.cuts.size(), doc.actionCount());
    std::printf("%6s %7s %7s  %s\n", "action", "first", "last", "name");
    for (int i = 0; i < doc.actionCount(); ++i) {
        const std::string& name = doc.actions[static_cast<std::size_t>(i)].name;
        std::printf("%6d %7d %7d  %s\n", i, doc.firstFrame(i), doc.lastFrame(i),
                    name.empty() ? "-" : name.c_str());
    }
}

void runCuts(const CutsArgs& a) {
    struct Op {
        const char* name;
        std::size_t args;
        const char* usage;
    };
    static const Op ops[] = {{"list", 0, "list"},          {"add", 1, "add FRAME"},
                             {"move", 2, "move FRAME TO"}, {"delete", 1, "delete FRAME"},
                             {"merge", 1, "merge ACTION"}, {"split", 2, "split ACTION FRAME"}};
    const Op* op = nullptr;
    for (const auto& o : ops) {
        if (a.op == o.name) op = &o;
    }
    if (!op) return fail("cuts: unknown operation '" + a.op + "' (list, add, move, delete, merge, split)");
    if (a.args.size() != op->args) return fail("cuts " + a.op + ": expected " + op->usage);
    if (a.json && a.op != "list") return fail("cuts " + a.op + ": --json goes with list only");

    auto opened = openFor(a.project, a.motion);
    if (!opened) return fail(opened.error().message);
    ProjectDocument& doc = **opened;
    const prep::ProjectMotion& m = *doc.project().findMotion(a.motion);
    if (a.op == "list") return listCuts(m, a.json);

    auto number = [&](std::size_t i, const char* what) {
        return parseInt(a.args[i], "cuts " + a.op + ": " + what);
    };
    Status st;
    if (a.op == "add" || a.op == "delete") {
        auto frame = number(0, "FRAME");
        if (!frame) return fail(frame.error().message);
        st = a.op == "add" ? doc.addCut(a.motion, *frame) : doc.removeCut(a.motion, *frame);
    } else if (a.op == "move") {
        auto frame = number(0, "FRAME");
        if (!frame) return fail(frame.error().message);
        auto to = number(1, "TO");
        if (!to) return fail(to.error().message);
        st = doc.moveCut(a.motion, *frame, *to);
    } else {
        auto action = resolveAction(m, a.args[0]);
        if (!action) return fail(a.project + ": " + action.error().message);
        if (a.op == "merge") {
            st = doc.mergeActions(a.motion, *action);
        } else {
            auto frame = number(1, "FRAME");
            if (!frame) return fail(frame.error().message);
            st = doc.splitAction(a.motion, *action, *frame);
        }
    }
    if (!st) return fail(a.project + ": cuts " + a.op + ": " + st.error().message);
    const std::string what = a.op + " " + a.args[0] + (a.args.size() > 1 ? " " + a.args[1] : "");
    saveAndReport(doc, a.project, "motion " + quoted(a.motion),
                  " (" + what + "; " +
                      std::to_string(doc.project().findMotion(a.motion)->actions.actionCount()) +
                      " actions)");
}

}  // namespace

void registerEdit(CLI::App& app) {
    {
        auto args = std::make_shared<AnnotateArgs>();
        auto* cmd = app.add_subcommand(
            "annotate", "Edit an action's name, annotations, proposals, joints, direction, defended part, ranges");
        cmd->footer(
            "ACTION is an index, or a name that exactly one action of the motion has (an all-digit ACTION is an\n"
            "index). The edits run in command-line order; the project is saved once, and only if all succeed.");
        args->cmd = cmd;
        // Options without a variable: runAnnotate reads them in parse order.
        const auto flag = [cmd](const std::string& name, const std::string& help) {
            return cmd->add_flag(name, help);
        };
        const auto option = [cmd](const std::string& name, const std::string& help, const std::string& type) {
            return cmd->add_option(name, help)
                ->expected(1)
                ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)
                ->type_name(type);
        };
        cmd->add_option("project", args->project, "Project file")->required();
        cmd->add_option("motion", args->motion, "Motion id")->required();
        cmd->add_option("action", args->action, "Action index, or its name when unique in the motion")
            ->required();
        option("--name", "Name the action ('' clears the name)", "NAME");
        option("--add", "Annotate with a vocabulary word (repeatable)", "WORD");
        option("--remove", "Remove an annotation (repeatable)", "WORD");
        auto* confirm = option("--confirm", "Confirm a proposed annotation (repeatable)", "WORD");
        auto* confirmAll = flag("--confirm-all", "Confirm every proposal");
        auto* reject = option("--reject", "Reject a proposed annotation (repeatable)", "WORD");
        auto* rejectAll = flag("--reject-all", "Reject every proposal");
        confirm->excludes(confirmAll);
        reject->excludes(rejectAll);
        confirmAll->excludes(rejectAll);
        option("--joints", "Joints used: skeleton names, comma-separated ('' clears them)", "A,B");
        auto* direction = option("--direction", "Attack direction (attacks)", "D");
        direction->excludes(flag("--no-direction", "Clear the attack direction"));
        auto* defended = option("--defended", "Defended body part (blocks, avoids)", "PART");
        defended->excludes(flag("--no-defended", "Clear the defended part"));
        auto* noRanges = flag("--no-ranges", "Clear the initial-condition ranges");
        for (const char* range : {"--distance", "--angle", "--facing", "--timing"}) {
            const std::string name = range;
            const std::string help =
                name == "--distance" ? "Initial condition: opponent distance MIN:MAX (m)"
                : name == "--angle"
                    ? "Initial condition: opponent direction MIN:MAX (degrees, 0 = in front, + = left)"
                : name == "--facing"
                    ? "Initial condition: opponent heading relative to mine MIN:MAX (degrees, 180 = facing)"
                    : "Initial condition: opponent action start offset MIN:MAX (s)";
            option(name, help + "; an action without ranges needs all four", "MIN:MAX")->excludes(noRanges);
        }
        cmd->callback([args] { runAnnotate(*args); });
    }
    {
        auto args = std::make_shared<CutsArgs>();
        auto* cmd = app.add_subcommand("cuts", "List or edit a motion's cuts: add, move, delete, merge, split");
        cmd->footer(
            "  list [--json] | add FRAME | move FRAME TO | delete FRAME | merge ACTION (with the next) |\n"
            "  split ACTION FRAME. Actions follow their cuts.\n"
            "ACTION is an index, or a name that exactly one action of the motion has (an all-digit ACTION is an\n"
            "index).");
        cmd->add_option("project", args->project, "Project file")->required();
        cmd->add_option("motion", args->motion, "Motion id")->required();
        cmd->add_option("operation", args->op, "list | add | move | delete | merge | split")->required();
        cmd->add_option("args", args->args, "FRAME, FRAME TO, ACTION or ACTION FRAME");
        cmd->add_flag("--json", args->json, "JSON output (list)");
        cmd->callback([args] { runCuts(*args); });
    }
}

}  // namespace fray::cli
