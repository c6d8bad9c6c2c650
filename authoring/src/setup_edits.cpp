// ProjectDocument's edits of scene setups and PatternLists (issue 23). Each
// one reads the section it edits, changes a copy, checks it the way the file
// reader would, and pushes one SectionCommand holding the section's old and
// new text, so undo gives back the very bytes.
#include <QImage>

#include <algorithm>
#include <cmath>

#include "fray/authoring/commands.h"
#include "fray/authoring/project_document.h"
#include "fray/core/atomic_file.h"
#include "fray/setup/graph_setup.h"
#include "fray/setup/convert.h"
#include "fray/setup/plan_setup.h"
#include "fray/prep/json_reader.h"  // FRAY_TRY

namespace fray::authoring {
namespace {

namespace fs = std::filesystem;
using setup::SceneSetup;

std::string inQ(const std::string& s) { return "'" + s + "'"; }
std::string who(const std::string& setup) { return "setup " + inQ(setup); }

bool finite(double x) { return std::isfinite(x); }

Status checkPoint(const setup::Point& p, const std::string& what) {
    if (!finite(p.x) || !finite(p.z) || std::fabs(p.x) > 1e5 || std::fabs(p.z) > 1e5) {
        return makeError(what + ": the position must be finite and within 100 km");
    }
    return {};
}

const char* const kPatternGroups[] = {"attack", "defence", "fall", "any"};

}  // namespace

// ---- plumbing -------------------------------------------------------------------

Result<std::vector<SceneSetup>> ProjectDocument::setups() const {
    return setup::projectSetups(project_, file_.empty() ? project_.name : file_.string());
}

Result<SceneSetup> ProjectDocument::sceneSetup(const std::string& name) const {
    auto list = setups();
    if (!list) return list.error();
    const SceneSetup* s = setup::findSetup(*list, name);
    if (!s) return makeError("the project has no setup " + inQ(name));
    return *s;
}

Status ProjectDocument::editSetups(const QString& text, const std::string& key, DragId drag, std::vector<ChangeEvent> events,
                                   const SetupChange& change) {
    auto list = setups();
    if (!list) return list.error();
    std::vector<SceneSetup> edited = *list;
    if (auto st = change(edited, events); !st) return st;
    if (edited == *list) return {};
    const std::string file = file_.empty() ? project_.name : file_.string();
    for (std::size_t i = 0; i < edited.size(); ++i) {
        const SceneSetup* was = setup::findSetup(*list, edited[i].name);
        if (was && *was == edited[i]) continue;  // read from the file: already checked
        if (auto st = setup::checkSetup(edited[i], file, "/scene/setups/" + std::to_string(i)); !st) return st;
    }
    std::optional<std::string> after;
    if (!edited.empty()) after = setup::setupsToJson(edited);
    undoStack_.push(new SectionCommand(this, text, setup::kSetupSection, std::move(after), key, std::move(events), drag));
    return {};
}

Status ProjectDocument::editSetup(const std::string& name, const QString& text, const std::string& key, DragId drag,
                                  ChangeEvent event, const std::function<Status(SceneSetup&)>& change) {
    event.setup = name;
    return editSetups(text, "setup/" + name + "/" + key, drag, {event}, [&](std::vector<SceneSetup>& list, std::vector<ChangeEvent>&) -> Status {
        SceneSetup* s = setup::findSetup(list, name);
        if (!s) return makeError("the project has no setup " + inQ(name));
        return change(*s);
    });
}

Status ProjectDocument::editTrajectory(const std::string& name, const std::string& character, const QString& text,
                                      const std::string& key, DragId drag,
                                      const std::function<Status(setup::Trajectory&)>& change) {
    ChangeEvent e{ChangeKind::SetupTrajectory, {}, -1, 0};
    e.character = character;
    return editSetup(name, text, "trajectory/" + character + "/" + key, drag, e, [&](SceneSetup& s) -> Status {
        auto it = std::find_if(s.trajectories.begin(), s.trajectories.end(),
                               [&](const setup::Trajectory& t) { return t.character == character; });
        if (it == s.trajectories.end()) return makeError(who(name) + ": " + inQ(character) + " has no trajectory");
        if (auto st = change(*it); !st) return makeError(who(name) + ", trajectory of " + inQ(character) + ": " + st.error().message);
        if (auto line = setup::sampleTrajectory(*it); !line) return makeError(who(name) + ": " + line.error().message);
        return {};
    });
}

// ---- setups -------------------------------------------------------------------------

Status ProjectDocument::addSetup(SceneSetup s) {
    if (auto st = setup::checkSetupName(s.name); !st) return st;
    const std::string name = s.name;
    ChangeEvent e{ChangeKind::SetupAdded, {}, -1, 0};
    e.setup = name;
    auto list = setups();
    if (!list) return list.error();
    e.index = static_cast<int>(list->size());
    return editSetups(QStringLiteral("Add setup %1").arg(QString::fromStdString(name)), "setups", 0, {e},
                      [&](std::vector<SceneSetup>& l, std::vector<ChangeEvent>&) -> Status {
                          if (setup::findSetup(l, name)) return makeError("a setup named " + inQ(name) + " already exists");
                          l.push_back(std::move(s));
                          return {};
                      });
}

Status ProjectDocument::addSetup(const std::string& name, setup::SetupKind kind) {
    if (auto st = setup::checkSetupName(name); !st) return st;
    SceneSetup s = setup::makeSetup(name, kind);
    // A new duel fights with the project's fighting takes (plan_setup.h), not every take's actions.
    if (kind == setup::SetupKind::Duel) {
        if (auto st = setup::applyActionSet(s, setup::defaultDuelActionSet(project_)); !st) return st;
    }
    return addSetup(std::move(s));
}

Status ProjectDocument::removeSetup(const std::string& name) {
    auto list = setups();
    if (!list) return list.error();
    const SceneSetup* s = setup::findSetup(*list, name);
    if (!s) return makeError("the project has no setup " + inQ(name));
    ChangeEvent e{ChangeKind::SetupRemoved, {}, static_cast<int>(s - list->data()), 0};
    e.setup = name;
    return editSetups(QStringLiteral("Remove setup %1").arg(QString::fromStdString(name)), "setups", 0, {e},
                      [&](std::vector<SceneSetup>& l, std::vector<ChangeEvent>&) -> Status {
                          l.erase(std::remove_if(l.begin(), l.end(), [&](const SceneSetup& x) { return x.name == name; }), l.end());
                          return {};
                      });
}

Status ProjectDocument::renameSetup(const std::string& from, const std::string& to) {
    if (from == to) return {};
    if (auto st = setup::checkSetupName(to); !st) return st;
    ChangeEvent e{ChangeKind::SetupRenamed, {}, -1, 0};
    e.setup = to;
    e.previousName = from;
    return editSetups(QStringLiteral("Rename setup %1").arg(QString::fromStdString(from)), "setups", 0, {e},
                      [&](std::vector<SceneSetup>& l, std::vector<ChangeEvent>&) -> Status {
                          SceneSetup* s = setup::findSetup(l, from);
                          if (!s) return makeError("the project has no setup " + inQ(from));
                          if (setup::findSetup(l, to)) return makeError("a setup named " + inQ(to) + " already exists");
                          s->name = to;
                          return {};
                      });
}

Status ProjectDocument::duplicateSetup(const std::string& name, const std::string& copyName) {
    auto s = sceneSetup(name);
    if (!s) return s.error();
    s->name = copyName;
    return addSetup(std::move(*s));
}

namespace {
// A two-colour image as a floor bitmap, read with Qt's image readers.
Result<setup::FloorPaint> readFloorImage(const fs::path& file, double metresPerPixel, setup::Point origin) {
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) return makeError(file.string() + ": no such file");
    QImage image;
    if (!image.load(QString::fromStdString(file.string()))) {
        return makeError(file.string() + ": not an image Fray can read (PNG, BMP, JPEG...); nothing was imported");
    }
    const QImage rgba = image.convertToFormat(QImage::Format_RGBA8888);
    std::vector<std::uint8_t> pixels(static_cast<std::size_t>(rgba.width()) * static_cast<std::size_t>(rgba.height()) * 4);
    for (int y = 0; y < rgba.height(); ++y) {
        const auto* row = rgba.constScanLine(y);
        std::copy(row, row + rgba.width() * 4, pixels.begin() + static_cast<std::ptrdiff_t>(y) * rgba.width() * 4);
    }
    return setup::floorFromRgba(rgba.width(), rgba.height(), pixels.data(), metresPerPixel, origin, file.string());
}
}  // namespace

Status ProjectDocument::importSetupFromSpec(const std::string& name, const fs::path& specFile) {
    auto text = readWholeFile(specFile, "the scene spec");
    if (!text) return text.error();
    auto imported = setup::importSpec(name, *text, specFile, [](const fs::path& file, double mpp, glm::vec2 origin) -> Result<sim::FloorBitmap> {
        auto paint = readFloorImage(file, mpp, {static_cast<double>(origin.x), static_cast<double>(origin.y)});
        if (!paint) return paint.error();
        sim::FloorBitmap floor = setup::toFloorBitmap(*paint);
        floor.origin = origin;
        return floor;
    });
    if (!imported) return imported.error();
    return addSetup(std::move(*imported));
}

Status ProjectDocument::replaceSetup(const std::string& name, SceneSetup replacement, const QString& text) {
    if (replacement.name != name) return makeError(who(name) + ": the replacement is named " + inQ(replacement.name));
    return editSetup(name, text, "all", 0, {ChangeKind::SetupParameters, {}, -1, 0}, [&](SceneSetup& s) -> Status {
        s = std::move(replacement);
        return {};
    });
}

Status ProjectDocument::checkSetupEdit(const SceneSetup& was, const SceneSetup& now) const {
    const std::string file = file_.empty() ? project_.name : file_.string();
    if (setup::isTreeExpansion(now.kind)) {
        // A duel's or chase's spec is read as simulate reads it (presets, weights, actions,
        // takes), against one catalogue for both checks.
        auto context = setup::planCheckContext(project_, file);
        if (!context) return context.error();
        if (auto after = setup::checkPlanSetup(now, *context); !after) {
            const auto before = setup::checkPlanSetup(was, *context);
            if (before || before.error().message != after.error().message) return after.error();
        }
    } else if (!setup::isGraphKind(now.kind)) {
        // A patch kind's spec is read as compose reads it (its numbers' ranges, the rat's speed...).
        auto patterns = patternSet();
        if (!patterns) return patterns.error();
        if (auto after = setup::checkComposeSetup(now, patterns->patterns); !after) {
            const auto before = setup::checkComposeSetup(was, patterns->patterns);
            if (before || before.error().message != after.error().message) return after.error();
        }
    }
    return {};
}

Status ProjectDocument::setSetupParameter(const std::string& name, const std::string& pointer, const std::string& json, DragId drag) {
    return editSetup(name, QStringLiteral("Set %1").arg(QString::fromStdString(pointer)), "param" + pointer, drag,
                     {ChangeKind::SetupParameters, {}, -1, 0},
                     [&](SceneSetup& s) -> Status {
                         const SceneSetup was = s;
                         if (auto st = setup::setParameter(s, pointer, json); !st) return st;
                         // An Interaction Graph setup's parameters are checked as they are set (the error names the field).
                         if (setup::isGraphKind(s.kind)) {
                             if (auto p = setup::graphParams(s, false); !p) return p.error();
                         }
                         // The others as simulate or compose reads them; an edit is refused when it brings a
                         // problem the setup did not have before.
                         return checkSetupEdit(was, s);
                     });
}

Status ProjectDocument::setFloorScale(const std::string& name, double metresPerPixel, DragId drag) {
    return editSetup(name, QStringLiteral("Set the floor's scale"), "floor_scale", drag, {ChangeKind::SetupFloor, {}, -1, 0},
                     [&](SceneSetup& s) -> Status {
                         const SceneSetup was = s;
                         if (auto st = setup::setFloorScale(s, metresPerPixel); !st) return st;
                         return checkSetupEdit(was, s);
                     });
}

// ---- placements and paths --------------------------------------------------------

Status ProjectDocument::setCharacterStart(const std::string& name, const std::string& character, const setup::Placement& start,
                                          DragId drag) {
    ChangeEvent e{ChangeKind::SetupPlacement, {}, -1, 0};
    e.character = character;
    return editSetup(name, QStringLiteral("Move %1").arg(QString::fromStdString(character)), "start/" + character, drag, e,
                     [&](SceneSetup& s) { return setup::setCharacterStart(s, character, start); });
}

Status ProjectDocument::moveTeam(const std::string& name, int side, double dx, double dz, DragId drag) {
    // (dx, dz) moves the team from where it is now: a drag passes each mouse
    // move's delta, and the merged step holds the sum.
    ChangeEvent e{ChangeKind::SetupPlacement, {}, side, 0};
    return editSetup(name, QStringLiteral("Move team %1").arg(side + 1), "team/" + std::to_string(side), drag, e,
                     [&](SceneSetup& s) { return setup::moveTeam(s, side, dx, dz); });
}

Status ProjectDocument::setDominoStarts(const std::string& name, std::vector<setup::DominoStartPoint> starts, DragId drag) {
    return editSetup(name, QStringLiteral("Set chain starts"), "domino_starts", drag, {ChangeKind::SetupPlacement, {}, -1, 0},
                     [&](SceneSetup& s) { return setup::setDominoStarts(s, starts); });
}

Status ProjectDocument::setRatPath(const std::string& name, std::vector<setup::Point> path, DragId drag) {
    return editSetup(name, QStringLiteral("Edit the rat's trajectory"), "rat_path", drag, {ChangeKind::SetupPaths, {}, -1, 0},
                     [&](SceneSetup& s) { return setup::setRatPath(s, path); });
}

Status ProjectDocument::setRunDirections(const std::string& name, std::vector<setup::RunDirection> directions, DragId drag) {
    return editSetup(name, QStringLiteral("Edit running directions"), "directions", drag, {ChangeKind::SetupPaths, {}, -1, 0},
                     [&](SceneSetup& s) { return setup::setRunDirections(s, directions); });
}

Status ProjectDocument::setTimedCommands(const std::string& name, std::vector<setup::TimedCommand> commands) {
    return editSetup(name, QStringLiteral("Edit commands"), "commands", 0, {ChangeKind::SetupPaths, {}, -1, 0},
                     [&](SceneSetup& s) { return setup::setTimedCommands(s, commands); });
}

// ---- trajectories -----------------------------------------------------------------

Status ProjectDocument::addTrajectory(const std::string& name, setup::Trajectory trajectory) {
    ChangeEvent e{ChangeKind::SetupTrajectory, {}, -1, 0};
    e.character = trajectory.character;
    return editSetup(name, QStringLiteral("Add trajectory"), "trajectories", 0, e, [&](SceneSetup& s) -> Status {
        if (s.kind == setup::SetupKind::GraphCarry) {
            if (trajectory.character != setup::kCarryPathCharacter) {
                return makeError(who(name) + ": a graph-carry setup's trajectory is the box's path (character 'box')");
            }
        } else if (!setup::isTreeExpansion(s.kind)) {
            return makeError(who(name) + ": trajectories with checkpoints belong to duel, chase and graph-carry setups");
        }
        if (setup::characterIndex(s, trajectory.character) < 0) {
            return makeError(who(name) + ": no character named " + inQ(trajectory.character));
        }
        for (const auto& t : s.trajectories) {
            if (t.character == trajectory.character) return makeError(who(name) + ": " + inQ(t.character) + " already has a trajectory");
        }
        for (const auto& p : trajectory.points) {
            if (auto st = checkPoint(p, who(name) + ", trajectory"); !st) return st;
        }
        auto line = setup::sampleTrajectory(trajectory);
        if (!line) return makeError(who(name) + ": " + line.error().message);
        for (const auto& c : trajectory.checkpoints) {
            if (auto st = checkPoint(c.pos, who(name) + ", checkpoint"); !st) return st;
        }
        std::stable_sort(trajectory.checkpoints.begin(), trajectory.checkpoints.end(),
                         [&](const setup::SetupCheckpoint& a, const setup::SetupCheckpoint& b) {
                             return setup::trajectoryParameter(*line, a.pos) < setup::trajectoryParameter(*line, b.pos);
                         });
        s.trajectories.push_back(std::move(trajectory));
        return {};
    });
}

Status ProjectDocument::removeTrajectory(const std::string& name, const std::string& character) {
    ChangeEvent e{ChangeKind::SetupTrajectory, {}, -1, 0};
    e.character = character;
    return editSetup(name, QStringLiteral("Remove trajectory"), "trajectories", 0, e, [&](SceneSetup& s) -> Status {
        const auto before = s.trajectories.size();
        std::erase_if(s.trajectories, [&](const setup::Trajectory& t) { return t.character == character; });
        if (s.trajectories.size() == before) return makeError(who(name) + ": " + inQ(character) + " has no trajectory");
        return {};
    });
}

Status ProjectDocument::addTrajectoryPoint(const std::string& name, const std::string& character, int index, setup::Point point) {
    if (auto st = checkPoint(point, who(name) + ", trajectory point"); !st) return st;
    return editTrajectory(name, character, QStringLiteral("Add trajectory point"), "points", 0, [&](setup::Trajectory& t) -> Status {
        if (t.shape != setup::TrajectoryShape::Polyline) {
            return makeError(std::string("a ") + setup::trajectoryShapeName(t.shape) + " has a fixed number of points: move them instead");
        }
        if (index < 0 || index > static_cast<int>(t.points.size())) {
            return makeError("point " + std::to_string(index) + " is out of range (0.." + std::to_string(t.points.size()) + ")");
        }
        t.points.insert(t.points.begin() + index, point);
        return {};
    });
}

Status ProjectDocument::removeTrajectoryPoint(const std::string& name, const std::string& character, int index) {
    return editTrajectory(name, character, QStringLiteral("Remove trajectory point"), "points", 0, [&](setup::Trajectory& t) -> Status {
        if (t.shape != setup::TrajectoryShape::Polyline) {
            return makeError(std::string("a ") + setup::trajectoryShapeName(t.shape) + " has a fixed number of points: move them instead");
        }
        if (index < 0 || index >= static_cast<int>(t.points.size())) {
            return makeError("point " + std::to_string(index) + " does not exist (the trajectory has " + std::to_string(t.points.size()) + ")");
        }
        if (t.points.size() == 1) return makeError("the trajectory would be empty: remove the trajectory instead");
        t.points.erase(t.points.begin() + index);
        return {};
    });
}

Status ProjectDocument::moveTrajectoryPoint(const std::string& name, const std::string& character, int index, setup::Point point,
                                            DragId drag) {
    if (auto st = checkPoint(point, who(name) + ", trajectory point"); !st) return st;
    return editTrajectory(name, character, QStringLiteral("Move trajectory point"), "point/" + std::to_string(index), drag,
                          [&](setup::Trajectory& t) -> Status {
                              if (index < 0 || index >= static_cast<int>(t.points.size())) {
                                  return makeError("point " + std::to_string(index) + " does not exist (the trajectory has " +
                                                   std::to_string(t.points.size()) + ")");
                              }
                              t.points[static_cast<std::size_t>(index)] = point;
                              return {};
                          });
}

Result<int> ProjectDocument::addCheckpoint(const std::string& name, const std::string& character, setup::SetupCheckpoint checkpoint) {
    if (auto st = checkPoint(checkpoint.pos, who(name) + ", checkpoint"); !st) return st.error();
    if (checkpoint.time && (!finite(*checkpoint.time) || *checkpoint.time < 0 || *checkpoint.time > 3600)) {
        return makeError(who(name) + ", checkpoint: the time must be in [0, 3600] s");
    }
    if (!checkpoint.action.empty()) {
        if (auto st = checkPatternAnnotation(checkpoint.action, who(name) + ", checkpoint"); !st) return st.error();
    }
    int at = -1;
    auto st = editTrajectory(name, character, QStringLiteral("Add checkpoint"), "checkpoints", 0, [&](setup::Trajectory& t) -> Status {
        auto line = setup::sampleTrajectory(t);
        if (!line) return line.error();
        const double s = setup::trajectoryParameter(*line, checkpoint.pos);
        at = 0;
        while (at < static_cast<int>(t.checkpoints.size()) &&
               setup::trajectoryParameter(*line, t.checkpoints[static_cast<std::size_t>(at)].pos) <= s) {
            ++at;
        }
        t.checkpoints.insert(t.checkpoints.begin() + at, checkpoint);
        return {};
    });
    if (!st) return st.error();
    return at;
}

Status ProjectDocument::removeCheckpoint(const std::string& name, const std::string& character, int index) {
    return editTrajectory(name, character, QStringLiteral("Remove checkpoint"), "checkpoints", 0, [&](setup::Trajectory& t) -> Status {
        if (index < 0 || index >= static_cast<int>(t.checkpoints.size())) {
            return makeError("checkpoint " + std::to_string(index) + " does not exist (there are " + std::to_string(t.checkpoints.size()) + ")");
        }
        t.checkpoints.erase(t.checkpoints.begin() + index);
        return {};
    });
}

Status ProjectDocument::moveCheckpoint(const std::string& name, const std::string& character, int index, setup::Point point,
                                       DragId drag) {
    if (auto st = checkPoint(point, who(name) + ", checkpoint"); !st) return st;
    return editTrajectory(name, character, QStringLiteral("Move checkpoint"), "checkpoint/" + std::to_string(index), drag,
                          [&](setup::Trajectory& t) -> Status {
                              if (index < 0 || index >= static_cast<int>(t.checkpoints.size())) {
                                  return makeError("checkpoint " + std::to_string(index) + " does not exist (there are " +
                                                   std::to_string(t.checkpoints.size()) + ")");
                              }
                              t.checkpoints[static_cast<std::size_t>(index)].pos = point;
                              return {};
                          });
}

Status ProjectDocument::setCheckpointTime(const std::string& name, const std::string& character, int index, std::optional<double> time,
                                          DragId drag) {
    if (time && (!finite(*time) || *time < 0 || *time > 3600)) {
        return makeError(who(name) + ", checkpoint " + std::to_string(index) + ": the time must be in [0, 3600] s");
    }
    return editTrajectory(name, character, QStringLiteral("Set checkpoint time"), "checkpoint_time/" + std::to_string(index), drag,
                          [&](setup::Trajectory& t) -> Status {
                              if (index < 0 || index >= static_cast<int>(t.checkpoints.size())) {
                                  return makeError("checkpoint " + std::to_string(index) + " does not exist (there are " +
                                                   std::to_string(t.checkpoints.size()) + ")");
                              }
                              t.checkpoints[static_cast<std::size_t>(index)].time = time;
                              return {};
                          });
}

Status ProjectDocument::setCheckpointAction(const std::string& name, const std::string& character, int index, const std::string& action) {
    if (!action.empty()) {
        if (auto st = checkPatternAnnotation(action, who(name) + ", checkpoint " + std::to_string(index)); !st) return st;
    }
    return editTrajectory(name, character, QStringLiteral("Set checkpoint action"), "checkpoint_action/" + std::to_string(index), 0,
                          [&](setup::Trajectory& t) -> Status {
                              if (index < 0 || index >= static_cast<int>(t.checkpoints.size())) {
                                  return makeError("checkpoint " + std::to_string(index) + " does not exist (there are " +
                                                   std::to_string(t.checkpoints.size()) + ")");
                              }
                              t.checkpoints[static_cast<std::size_t>(index)].action = action;
                              return {};
                          });
}

// ---- floor ----------------------------------------------------------------------------

Result<std::vector<setup::PixelChange>> ProjectDocument::paintFloor(const std::string& name, const setup::FloorStroke& stroke, DragId drag) {
    std::vector<setup::PixelChange> changes;
    ChangeEvent e{ChangeKind::SetupFloor, {}, -1, 0};
    e.setup = name;
    static const char* const names[] = {"Brush stroke", "Eraser stroke", "Fill", "Text stamp"};
    const QString text = QString::fromLatin1(names[static_cast<int>(stroke.tool)]);
    auto st = editSetups(text, "setup/" + name + "/floor", drag, {e}, [&](std::vector<SceneSetup>& list, std::vector<ChangeEvent>& events) -> Status {
        SceneSetup* s = setup::findSetup(list, name);
        if (!s) return makeError("the project has no setup " + inQ(name));
        if (!s->floor) return makeError(who(name) + " has no floor bitmap (import an image or set a floor first)");
        auto ch = setup::applyStroke(*s->floor, stroke);
        if (!ch) return makeError(who(name) + ": " + ch.error().message);
        changes = std::move(*ch);
        const auto r = setup::changedRect(*s->floor, changes);
        events.front().pixels = {r.x, r.y, r.width, r.height};
        if (stroke.startTime && s->kind == setup::SetupKind::Domino) {
            // The falling letters: a chain starts on the stroke (each letter) at its time.
            auto all = setup::dominoStarts(*s);
            for (const auto& add : setup::strokeStarts(*s->floor, stroke)) all.push_back(add);
            if (auto ok = setup::setDominoStarts(*s, all); !ok) return ok;
            ChangeEvent p{ChangeKind::SetupPlacement, {}, -1, 0};
            p.setup = name;
            events.push_back(p);
        }
        return {};
    });
    if (!st) return st.error();
    return changes;
}

Status ProjectDocument::setFloor(const std::string& name, std::optional<setup::FloorPaint> floor, const QString& text) {
    if (floor) {
        if (floor->empty() || floor->width > setup::kMaxFloorPixels || floor->height > setup::kMaxFloorPixels ||
            floor->painted.size() != static_cast<std::size_t>(floor->width) * static_cast<std::size_t>(floor->height)) {
            return makeError(who(name) + ": a floor bitmap must be 1 to " + std::to_string(setup::kMaxFloorPixels) +
                             " pixels a side, with one value per pixel");
        }
        if (!(floor->metresPerPixel > 0.001) || floor->metresPerPixel > 10) {
            return makeError(who(name) + ": metres per pixel must be in (0.001, 10]");
        }
        if (auto st = checkPoint(floor->origin, who(name) + ", floor origin"); !st) return st;
        for (auto& b : floor->painted) b = b ? 1 : 0;
    }
    return editSetup(name, text, "floor", 0, {ChangeKind::SetupFloor, {}, -1, 0}, [&](SceneSetup& s) -> Status {
        s.floor = std::move(floor);
        return {};
    });
}

Status ProjectDocument::importFloorImage(const std::string& name, const fs::path& file, double metresPerPixel, setup::Point origin) {
    auto floor = readFloorImage(file, metresPerPixel, origin);
    if (!floor) return floor.error();
    return setFloor(name, std::move(*floor), QStringLiteral("Import floor bitmap"));
}

// ---- pins and verdicts --------------------------------------------------------------

Status ProjectDocument::addPin(const std::string& name, const setup::Pin& pin) {
    if (pin.character.empty() || pin.action.empty()) return makeError(who(name) + ": a pin needs a character and an action");
    if (!finite(pin.time) || pin.time < 0 || pin.time > 3600) return makeError(who(name) + ": a pin's time must be in [0, 3600] s");
    return editSetup(name, QStringLiteral("Pin %1").arg(QString::fromStdString(pin.action)), "pins", 0,
                     {ChangeKind::SetupPins, {}, -1, 0}, [&](SceneSetup& s) -> Status {
                         if (setup::isTreeExpansion(s.kind) && setup::characterIndex(s, pin.character) < 0) {
                             return makeError(who(name) + ": no character named " + inQ(pin.character));
                         }
                         for (const auto& p : s.pins) {
                             if (p.character == pin.character && std::fabs(p.time - pin.time) < 1e-9) {
                                 return makeError(who(name) + ": " + inQ(pin.character) + " already has a pin at this time");
                             }
                         }
                         auto at = std::find_if(s.pins.begin(), s.pins.end(), [&](const setup::Pin& p) {
                             return std::tie(p.character, p.time) > std::tie(pin.character, pin.time);
                         });
                         s.pins.insert(at, pin);
                         return {};
                     });
}

Status ProjectDocument::setPin(const std::string& name, const setup::Pin& pin) {
    if (pin.character.empty() || pin.action.empty()) return makeError(who(name) + ": a pin needs a character and an action");
    if (!finite(pin.time) || pin.time < 0 || pin.time > 3600) return makeError(who(name) + ": a pin's time must be in [0, 3600] s");
    return editSetup(name, QStringLiteral("Replace with %1").arg(QString::fromStdString(pin.action)), "pins", 0,
                     {ChangeKind::SetupPins, {}, -1, 0}, [&](SceneSetup& s) -> Status {
                         if (!setup::isTreeExpansion(s.kind)) {
                             return makeError(who(name) + ": a " + setup::setupKindName(s.kind) +
                                              " setup is composed from Interaction Patches: pins are honoured by duel and chase setups only");
                         }
                         if (setup::characterIndex(s, pin.character) < 0) return makeError(who(name) + ": no character named " + inQ(pin.character));
                         for (auto& p : s.pins) {
                             if (p.character == pin.character && std::fabs(p.time - pin.time) < 1e-9) {
                                 p.action = pin.action;
                                 return {};
                             }
                         }
                         auto at = std::find_if(s.pins.begin(), s.pins.end(), [&](const setup::Pin& p) {
                             return std::tie(p.character, p.time) > std::tie(pin.character, pin.time);
                         });
                         s.pins.insert(at, pin);
                         return {};
                     });
}

Status ProjectDocument::removePin(const std::string& name, int index) {
    return editSetup(name, QStringLiteral("Remove pin"), "pins", 0, {ChangeKind::SetupPins, {}, index, 0}, [&](SceneSetup& s) -> Status {
        if (index < 0 || index >= static_cast<int>(s.pins.size())) {
            return makeError(who(name) + ": pin " + std::to_string(index) + " does not exist (there are " + std::to_string(s.pins.size()) + ")");
        }
        s.pins.erase(s.pins.begin() + index);
        return {};
    });
}

Status ProjectDocument::setPatchVerdict(const std::string& name, int patch, Verdict verdict) {
    if (patch < 0) return makeError(who(name) + ": patch " + std::to_string(patch) + " is not a patch index");
    static const char* const texts[] = {"Clear patch verdict", "Keep patch", "Reject patch"};
    return editSetup(name, QString::fromLatin1(texts[static_cast<int>(verdict)]), "patches", 0,
                     {ChangeKind::SetupPatches, {}, patch, 0}, [&](SceneSetup& s) -> Status {
                         auto& kept = s.patches.kept;
                         auto& rejected = s.patches.rejected;
                         std::erase(kept, patch);
                         std::erase(rejected, patch);
                         auto& into = verdict == Verdict::Keep ? kept : rejected;
                         if (verdict != Verdict::None) into.insert(std::lower_bound(into.begin(), into.end(), patch), patch);
                         return {};
                     });
}

// ---- hand-made patches ---------------------------------------------------------------

Result<std::vector<setup::HandMadePatch>> ProjectDocument::handMadePatches() const {
    return setup::projectHandMadePatches(project_, file_.empty() ? project_.name : file_.string());
}

Status ProjectDocument::addHandMadePatch(setup::HandMadePatch recipe, const std::string& name, int patch) {
    FRAY_TRY(list, handMadePatches());
    if (recipe.pattern.empty()) return makeError("hand-made patch: choose the PatternList it follows");
    if (recipe.actions[0].empty()) return makeError("hand-made patch: character 1 needs at least one action");
    if (!std::isfinite(recipe.initial.r) || recipe.initial.r < 0 || recipe.initial.r > 10 || !std::isfinite(recipe.initial.theta1) ||
        !std::isfinite(recipe.initial.theta2) || !std::isfinite(recipe.initial.delay) || recipe.initial.delay < 0 || recipe.initial.delay > 10) {
        return makeError("hand-made patch: the initial configuration must have r in [0, 10] m, finite angles and a delay in [0, 10] s");
    }
    if (!name.empty()) {
        FRAY_TRY(s, sceneSetup(name));
        (void)s;
        if (patch < 0) return makeError(who(name) + ": patch " + std::to_string(patch) + " is not a patch index");
    }
    list.push_back(std::move(recipe));
    ChangeEvent e{ChangeKind::SetupPatches, {}, patch, 0};
    e.setup = name;
    undoStack_.beginMacro(QStringLiteral("Add hand-made patch"));
    undoStack_.push(new SectionCommand(this, QStringLiteral("Add hand-made patch"), setup::kHandMadeSection,
                                       setup::handMadePatchesToJson(list), "hand_made", {e}));
    Status kept;
    if (!name.empty()) kept = setPatchVerdict(name, patch, Verdict::Keep);
    undoStack_.endMacro();
    if (!kept) {
        undoStack_.undo();
        return kept;
    }
    return {};
}

Status ProjectDocument::removeHandMadePatch(int index) {
    FRAY_TRY(list, handMadePatches());
    if (index < 0 || index >= static_cast<int>(list.size())) {
        return makeError("hand-made patch " + std::to_string(index) + " does not exist (there are " + std::to_string(list.size()) + ")");
    }
    list.erase(list.begin() + index);
    std::optional<std::string> after;
    if (!list.empty()) after = setup::handMadePatchesToJson(list);
    undoStack_.push(new SectionCommand(this, QStringLiteral("Remove hand-made patch"), setup::kHandMadeSection, std::move(after),
                                       "hand_made", {ChangeEvent{ChangeKind::SetupPatches, {}, index, 0}}));
    return {};
}

// ---- PatternLists -------------------------------------------------------------------

Result<sim::PatternSet> ProjectDocument::patternSet() const {
    return sim::projectPatterns(project_, file_.empty() ? project_.name : file_.string());
}

Status ProjectDocument::checkPatternAnnotation(const std::string& annotation, const std::string& where) const {
    std::string word = annotation;
    if (!word.empty() && word[0] == '@') {
        word = word.substr(1);
    } else if (annotation != word || where.find("checkpoint") != std::string::npos) {
        // A checkpoint's action may also be an action name.
        for (const auto& m : project_.motions) {
            for (const auto& a : m.actions.actions) {
                if (a.name == annotation) return {};
            }
        }
        if (where.find("checkpoint") != std::string::npos) {
            return makeError(where + ": " + inQ(annotation) + " is neither \"@annotation\" nor the name of an action of the project");
        }
    }
    if (std::find(std::begin(kPatternGroups), std::end(kPatternGroups), word) != std::end(kPatternGroups)) return {};
    if (std::find(project_.vocabulary.begin(), project_.vocabulary.end(), word) == project_.vocabulary.end()) {
        return makeError(where + ": annotation " + inQ(word) + " is not in the project vocabulary (nor attack, defence, fall, any)");
    }
    for (const auto& m : project_.motions) {
        for (const auto& a : m.actions.actions) {
            if (std::find(a.annotations.begin(), a.annotations.end(), word) != a.annotations.end()) return {};
        }
    }
    return makeError(where + ": no action of the project has annotation " + inQ(word));
}

Status ProjectDocument::editPatterns(const QString& text, const std::string& key, DragId drag, const std::string& pattern,
                                     const std::function<Status(sim::PatternSet&)>& change) {
    auto set = patternSet();
    if (!set) return set.error();
    sim::PatternSet edited = *set;
    if (auto st = change(edited); !st) return st;
    if (edited.patterns == set->patterns && edited.ranges == set->ranges) return {};
    prep::Project probe;
    probe.vocabulary = project_.vocabulary;
    sim::setProjectPatterns(probe, edited);
    // What the file reader would refuse is refused now.
    if (auto back = sim::projectPatterns(probe, "pattern lists"); !back) return back.error();
    ChangeEvent e{ChangeKind::PatternLists, {}, -1, 0};
    e.setup = pattern;
    undoStack_.push(new SectionCommand(this, text, sim::kPatternSection, probe.laterSections[sim::kPatternSection], "patterns/" + key,
                                       {e}, drag));
    return {};
}

Status ProjectDocument::addPattern(sim::PatternList pattern) {
    if (pattern.name.empty()) return makeError("a PatternList needs a name");
    for (std::size_t i = 0; i < pattern.entries.size(); ++i) {
        if (pattern.entries[i].character != 0 && pattern.entries[i].character != 1) {
            return makeError("pattern " + inQ(pattern.name) + ", row " + std::to_string(i + 1) + ": the character must be 1 or 2");
        }
        if (auto st = checkPatternAnnotation(pattern.entries[i].annotation, "pattern " + inQ(pattern.name) + ", row " + std::to_string(i + 1)); !st) {
            return st;
        }
    }
    const std::string name = pattern.name;
    return editPatterns(QStringLiteral("Add pattern %1").arg(QString::fromStdString(name)), "list", 0, name,
                        [&](sim::PatternSet& set) -> Status {
                            if (set.find(name)) return makeError("a PatternList named " + inQ(name) + " already exists");
                            set.patterns.push_back(std::move(pattern));
                            return {};
                        });
}

Status ProjectDocument::removePattern(const std::string& name) {
    return editPatterns(QStringLiteral("Remove pattern %1").arg(QString::fromStdString(name)), "list", 0, name,
                        [&](sim::PatternSet& set) -> Status {
                            const auto before = set.patterns.size();
                            std::erase_if(set.patterns, [&](const sim::PatternList& p) { return p.name == name; });
                            if (set.patterns.size() == before) return makeError("the project has no PatternList " + inQ(name));
                            return {};
                        });
}

Status ProjectDocument::renamePattern(const std::string& from, const std::string& to) {
    if (from == to) return {};
    if (to.empty()) return makeError("a PatternList needs a name");
    return editPatterns(QStringLiteral("Rename pattern %1").arg(QString::fromStdString(from)), "list", 0, to,
                        [&](sim::PatternSet& set) -> Status {
                            if (set.find(to)) return makeError("a PatternList named " + inQ(to) + " already exists");
                            for (auto& p : set.patterns) {
                                if (p.name == from) {
                                    p.name = to;
                                    return {};
                                }
                            }
                            return makeError("the project has no PatternList " + inQ(from));
                        });
}

namespace {
Result<sim::PatternList*> findPattern(sim::PatternSet& set, const std::string& name) {
    for (auto& p : set.patterns) {
        if (p.name == name) return &p;
    }
    return makeError("the project has no PatternList " + inQ(name));
}
}  // namespace

Status ProjectDocument::addPatternRow(const std::string& pattern, int index, sim::PatternEntry row) {
    const std::string where = "pattern " + inQ(pattern) + ", row " + std::to_string(index + 1);
    if (row.character != 0 && row.character != 1) return makeError(where + ": the character must be 1 or 2");
    if (auto st = checkPatternAnnotation(row.annotation, where); !st) return st;
    return editPatterns(QStringLiteral("Add row"), pattern + "/rows", 0, pattern, [&](sim::PatternSet& set) -> Status {
        FRAY_TRY(p, findPattern(set, pattern));
        if (index < 0 || index > static_cast<int>(p->entries.size())) {
            return makeError(where + ": out of range (1.." + std::to_string(p->entries.size() + 1) + ")");
        }
        p->entries.insert(p->entries.begin() + index, row);
        return {};
    });
}

Status ProjectDocument::setPatternRow(const std::string& pattern, int index, sim::PatternEntry row) {
    const std::string where = "pattern " + inQ(pattern) + ", row " + std::to_string(index + 1);
    if (row.character != 0 && row.character != 1) return makeError(where + ": the character must be 1 or 2");
    if (auto st = checkPatternAnnotation(row.annotation, where); !st) return st;
    return editPatterns(QStringLiteral("Edit row"), pattern + "/rows", 0, pattern, [&](sim::PatternSet& set) -> Status {
        FRAY_TRY(p, findPattern(set, pattern));
        if (index < 0 || index >= static_cast<int>(p->entries.size())) return makeError(where + ": no such row");
        p->entries[static_cast<std::size_t>(index)] = row;
        return {};
    });
}

Status ProjectDocument::removePatternRow(const std::string& pattern, int index) {
    const std::string where = "pattern " + inQ(pattern) + ", row " + std::to_string(index + 1);
    return editPatterns(QStringLiteral("Remove row"), pattern + "/rows", 0, pattern, [&](sim::PatternSet& set) -> Status {
        FRAY_TRY(p, findPattern(set, pattern));
        if (index < 0 || index >= static_cast<int>(p->entries.size())) return makeError(where + ": no such row");
        p->entries.erase(p->entries.begin() + index);
        return {};
    });
}

Status ProjectDocument::movePatternRow(const std::string& pattern, int from, int to) {
    if (from == to) return {};
    return editPatterns(QStringLiteral("Move row"), pattern + "/rows", 0, pattern, [&](sim::PatternSet& set) -> Status {
        FRAY_TRY(p, findPattern(set, pattern));
        const int n = static_cast<int>(p->entries.size());
        if (from < 0 || from >= n || to < 0 || to >= n) {
            return makeError("pattern " + inQ(pattern) + ": cannot move row " + std::to_string(from + 1) + " to " +
                             std::to_string(to + 1) + " (it has " + std::to_string(n) + " rows)");
        }
        const sim::PatternEntry row = p->entries[static_cast<std::size_t>(from)];
        p->entries.erase(p->entries.begin() + from);
        p->entries.insert(p->entries.begin() + to, row);
        return {};
    });
}

Status ProjectDocument::setPatternWeights(const std::string& pattern, sim::PatternWeights weights, DragId drag) {
    if (!finite(weights.contact) || !finite(weights.distance) || !finite(weights.timing) || weights.contact < 0 ||
        weights.distance < 0 || weights.timing < 0 || weights.contact + weights.distance + weights.timing <= 0) {
        return makeError("pattern " + inQ(pattern) + ": weights must be finite, not negative, and one of them positive");
    }
    return editPatterns(QStringLiteral("Set pattern weights"), pattern + "/weights", drag, pattern, [&](sim::PatternSet& set) -> Status {
        FRAY_TRY(p, findPattern(set, pattern));
        p->weights = weights;
        return {};
    });
}

Status ProjectDocument::setPatternThreshold(const std::string& pattern, double threshold, DragId drag) {
    if (!finite(threshold) || threshold < 0 || threshold > 1) {
        return makeError("pattern " + inQ(pattern) + ": the threshold must lie within [0, 1]");
    }
    return editPatterns(QStringLiteral("Set pattern threshold"), pattern + "/threshold", drag, pattern, [&](sim::PatternSet& set) -> Status {
        FRAY_TRY(p, findPattern(set, pattern));
        p->threshold = threshold;
        return {};
    });
}

Status ProjectDocument::setInitialRange(const std::string& annotation, std::optional<sim::InitialRange> range, DragId drag) {
    const std::string where = "initial conditions of " + inQ(annotation);
    if (auto st = checkPatternAnnotation(annotation, where); !st) return st;
    if (range) {
        const auto& r = *range;
        for (double x : {r.minDistance, r.maxDistance, r.minAngle, r.maxAngle, r.minDelay, r.maxDelay}) {
            if (!finite(x)) return makeError(where + ": every bound must be finite");
        }
        if (r.maxDistance < r.minDistance || r.maxAngle < r.minAngle || r.maxDelay < r.minDelay) {
            return makeError(where + ": a range's max is below its min");
        }
    }
    return editPatterns(QStringLiteral("Set initial conditions"), "range/" + annotation, drag, {}, [&](sim::PatternSet& set) -> Status {
        auto it = std::find_if(set.ranges.begin(), set.ranges.end(), [&](const auto& r) { return r.first == annotation; });
        if (!range) {
            if (it != set.ranges.end()) set.ranges.erase(it);
        } else if (it != set.ranges.end()) {
            it->second = *range;
        } else {
            set.ranges.emplace_back(annotation, *range);
        }
        return {};
    });
}

}  // namespace fray::authoring
