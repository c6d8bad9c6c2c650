// MainWindow: editing a generated interaction (issue 23 item 7, the thesis'
// future work 7.2.5). A right click on an action bar of the Gantt track opens
// its menu: "Replace with" the actions that fit there, "Pin" the action
// chosen, "Unpin" a pinned one. Each is one undo command on the setup's pins
// (ProjectDocument::setPin/addPin/removePin); the live re-plan plans the
// scene again around them (docs/EDITOR.md "Editing a generated interaction",
// docs/TREE_EXPANSION.md "Pins").
#include <QAction>
#include <QMenu>
#include <QStatusBar>
#include <algorithm>
#include <cmath>
#include <map>

#include "fray/authoring/project_document.h"
#include "fray/setup/convert.h"
#include "fray/sim/planner.h"
#include "fray/sim/spec.h"
#include "gantt_view.h"
#include "main_window.h"

namespace fray::editor {

namespace {

QString qs(const std::string& s) { return QString::fromStdString(s); }

}  // namespace

QStringList MainWindow::actionsFittingBar(int row, int bar, QString* why) const {
    const auto no = [&](const QString& reason) {
        if (why) *why = reason;
        return QStringList();
    };
    if (!scene_ || !sceneIsPreview_ || !doc_) return no("Generate a scene first: its actions can then be edited");
    if (previewSetup_.isEmpty()) return no("This scene comes from a spec file: import it as a setup (Scene panel) to edit its actions");
    const auto& chars = scene_->scene().characters;
    if (row < 0 || row >= static_cast<int>(chars.size())) return no("No such character");
    const auto& track = chars[static_cast<std::size_t>(row)].track;
    if (bar < 0 || bar >= static_cast<int>(track.size())) return no("No such action");
    auto st = doc_->sceneSetup(previewSetup_.toStdString());
    if (!st) return no(qs(st.error().message));
    if (setup::isSimulateKind(st->kind) && !setup::isTreeExpansion(st->kind)) {
        return no(QString("A %1 scene is played by the Interaction Graph's policies, decision by look-up: only duel and chase setups "
                          "(tree expansion) plan around pinned actions")
                      .arg(setup::setupKindName(st->kind)));
    }
    if (!setup::isTreeExpansion(st->kind)) {
        return no(QString("A %1 scene is composed from Interaction Patches: only duel and chase setups (tree expansion) "
                          "plan around pinned actions")
                      .arg(setup::setupKindName(st->kind)));
    }
    const sim::ActionInstance& inst = track[static_cast<std::size_t>(bar)];
    if (inst.forced) return no("A reaction to a hit is forced by the hit, not chosen: it cannot be replaced or pinned");
    if (bar == 0) return no("The start action is not a decision: pin a later action");
    const sim::ActionLibrary& lib = scene_->library();
    auto presets = sim::projectPresets(doc_->project(), projectFile_.toStdString());
    if (!presets) return no(qs(presets.error().message));
    auto spec = setup::toSceneSpec(*st, lib, *presets);
    if (!spec) return no(qs(spec.error().message));
    if (row >= static_cast<int>(spec->characters.size())) return no("The setup changed since the scene was planned: generate it again");
    const std::vector<int>& allowed = spec->characters[static_cast<std::size_t>(row)].allowed;
    const int prev = track[static_cast<std::size_t>(bar) - 1].action;
    const auto& actions = lib.actions();
    const sim::LibraryAction& mine = actions[static_cast<std::size_t>(inst.action)];
    std::map<std::string, bool> names;  // sorted, unique
    for (int a : allowed) {
        const sim::LibraryAction& x = actions[static_cast<std::size_t>(a)];
        if (x.is(sim::kReactive) || x.name.empty() || x.name == mine.name) continue;
        const auto& next = lib.next()[static_cast<std::size_t>(prev)];
        const bool graph = std::binary_search(next.begin(), next.end(), a);
        const bool same = std::any_of(x.annotations.begin(), x.annotations.end(), [&](const std::string& w) {
            return std::find(mine.annotations.begin(), mine.annotations.end(), w) != mine.annotations.end();
        });
        if (graph || same) names[x.name] = true;
    }
    QStringList out;
    for (const auto& [name, ok] : names) out << qs(name);
    if (out.isEmpty()) return no("No other action of this character fits here");
    return out;
}

QMenu* MainWindow::ganttBarMenu(int row, int bar) {
    auto* menu = new QMenu(this);
    menu->setObjectName("ganttBarMenu");
    QString why;
    const QStringList fits = actionsFittingBar(row, bar, &why);
    QMenu* replace = menu->addMenu("Replace with");
    replace->setObjectName("ganttReplaceMenu");
    const bool editable = why.isEmpty() || !fits.isEmpty();
    const GanttBar* gb = nullptr;
    if (row >= 0 && row < static_cast<int>(gantt_->data().rows.size())) {
        const auto& bars = gantt_->data().rows[static_cast<std::size_t>(row)].bars;
        if (bar >= 0 && bar < static_cast<int>(bars.size())) gb = &bars[static_cast<std::size_t>(bar)];
    }
    if (fits.isEmpty()) {
        replace->setEnabled(false);
        replace->setToolTip(why);
    }
    const sim::ActionLibrary* lib = scene_ ? &scene_->library() : nullptr;
    for (const QString& name : fits) {
        QString text = name;
        if (lib) {
            for (const sim::LibraryAction& x : lib->actions()) {
                if (qs(x.name) == name && !x.annotations.empty()) {
                    text += "  (" + qs(x.annotations.front()) + ")";
                    break;
                }
            }
        }
        QAction* a = replace->addAction(text, this, [this, row, bar, name] { replaceGanttBar(row, bar, name); });
        a->setObjectName("replace:" + name);
    }
    const bool pinned = gb && gb->pin >= 0;
    QAction* pin = menu->addAction(gb ? QString("Pin '%1' here").arg(gb->label) : QString("Pin"), this,
                                   [this, row, bar] { pinGanttBar(row, bar); });
    pin->setObjectName("ganttPin");
    pin->setEnabled(editable && !fits.isEmpty() && !pinned);
    QAction* unpin = menu->addAction("Unpin", this, [this, row, bar] { unpinGanttBar(row, bar); });
    unpin->setObjectName("ganttUnpin");
    unpin->setEnabled(pinned);
    if (!why.isEmpty()) {
        menu->addSeparator();
        QAction* note = menu->addAction(why);
        note->setObjectName("ganttMenuNote");
        note->setEnabled(false);
    }
    return menu;
}

bool MainWindow::replaceGanttBar(int row, int bar, const QString& action) {
    QString why;
    const QStringList fits = actionsFittingBar(row, bar, &why);
    if (!fits.contains(action)) {
        showError("Replace action", why.isEmpty() ? QString("'%1' does not fit there").arg(action) : why);
        return false;
    }
    const sim::SceneCharacter& c = scene_->scene().characters[static_cast<std::size_t>(row)];
    const sim::ActionInstance& inst = c.track[static_cast<std::size_t>(bar)];
    // A pinned bar keeps its pin's time (the pin is edited); else the bar's start.
    double time = inst.start;
    const auto& bars = gantt_->data().rows;
    if (row < static_cast<int>(bars.size()) && bar < static_cast<int>(bars[static_cast<std::size_t>(row)].bars.size())) {
        const int pin = bars[static_cast<std::size_t>(row)].bars[static_cast<std::size_t>(bar)].pin;
        if (pin >= 0 && pin < static_cast<int>(previewPins_.size())) time = previewPins_[static_cast<std::size_t>(pin)].time;
    }
    if (Status st = doc_->setPin(previewSetup_.toStdString(), {c.name, time, action.toStdString()}); !st) {
        showError("Replace action", qs(st.error().message));
        return false;
    }
    statusBar()->showMessage(QString("%1 plays %2 from %3 s (pinned); the scene is planned again around it")
                                 .arg(qs(c.name), action)
                                 .arg(time, 0, 'f', 2),
                             10000);
    return true;
}

bool MainWindow::pinGanttBar(int row, int bar) {
    QString why;
    actionsFittingBar(row, bar, &why);
    if (!why.isEmpty()) {
        showError("Pin action", why);
        return false;
    }
    const sim::SceneCharacter& c = scene_->scene().characters[static_cast<std::size_t>(row)];
    const sim::ActionInstance& inst = c.track[static_cast<std::size_t>(bar)];
    const std::string name = scene_->library().actions()[static_cast<std::size_t>(inst.action)].name;
    if (Status st = doc_->addPin(previewSetup_.toStdString(), {c.name, inst.start, name}); !st) {
        showError("Pin action", qs(st.error().message));
        return false;
    }
    statusBar()->showMessage(QString("%1 keeps %2 at %3 s (pinned)").arg(qs(c.name), qs(name)).arg(inst.start, 0, 'f', 2), 10000);
    return true;
}

bool MainWindow::unpinGanttBar(int row, int bar) {
    const auto& rows = gantt_->data().rows;
    const int pin = row >= 0 && row < static_cast<int>(rows.size()) && bar >= 0 &&
                            bar < static_cast<int>(rows[static_cast<std::size_t>(row)].bars.size())
                        ? rows[static_cast<std::size_t>(row)].bars[static_cast<std::size_t>(bar)].pin
                        : -1;
    if (pin < 0 || pin >= static_cast<int>(previewPins_.size()) || !doc_ || previewSetup_.isEmpty()) {
        showError("Unpin action", "This action is not pinned");
        return false;
    }
    // The same pin in the setup now (its index may have moved).
    auto st = doc_->sceneSetup(previewSetup_.toStdString());
    if (!st) {
        showError("Unpin action", qs(st.error().message));
        return false;
    }
    const setup::Pin& was = previewPins_[static_cast<std::size_t>(pin)];
    const auto it = std::find(st->pins.begin(), st->pins.end(), was);
    if (it == st->pins.end()) {
        showError("Unpin action", "The pin was changed since the scene was planned: wait for the re-plan");
        return false;
    }
    if (Status s = doc_->removePin(previewSetup_.toStdString(), static_cast<int>(it - st->pins.begin())); !s) {
        showError("Unpin action", qs(s.error().message));
        return false;
    }
    statusBar()->showMessage(QString("%1 no longer pinned at %2 s").arg(qs(was.character)).arg(was.time, 0, 'f', 2), 10000);
    return true;
}

}  // namespace fray::editor
