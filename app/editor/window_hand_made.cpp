// MainWindow: the hand-made patch (issue 23's patch browser). The dialog
// builds a patch action by action: a PatternList and an initial
// configuration, then character 1's and character 2's actions picked from
// the action library in turn; Evaluate plays them through the patch engine
// (sim::addHandMadePatch: hits, reactions, the pattern's rules); "Add as
// kept" stores the recipe in the project and keeps the patch in the current
// setup (one undo step). The library the editor composes from is the
// generated patches followed by the project's hand-made ones, rebuilt
// whenever those change (an undo included) and written to PROJECT.patches.
#include <QComboBox>
#include <QDialog>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QListWidget>
#include <QPushButton>
#include <QStatusBar>
#include <QVBoxLayout>
#include <cstdio>
#include <numbers>

#include "fray/authoring/project_document.h"
#include "main_window.h"
#include "patch_browser.h"
#include "scene_generation.h"

namespace fray::editor {

namespace {
QString qs(const std::string& s) { return QString::fromStdString(s); }
constexpr double kDeg = std::numbers::pi / 180.0;
}  // namespace

void MainWindow::rebuildPatchLibrary() {
    if (!doc_ || !patchGenerated_ || !patchSession_) return;
    const auto& sections = doc_->project().laterSections;
    const auto it = sections.find(setup::kHandMadeSection);
    const std::string now = it == sections.end() ? std::string() : it->second;
    if (now == handMadeApplied_ && patchLibrary_) return;
    const bool had = !handMadeApplied_.empty();
    handMadeApplied_ = now;
    auto recipes = doc_->handMadePatches();
    if (!recipes) {
        toolMessage("The project's hand-made patches cannot be read: " + qs(recipes.error().message), true);
        return;
    }
    if (recipes->empty() && !had) {  // the generated library as it is (already written)
        patchLibrary_ = patchGenerated_;
        return;
    }
    auto lib = std::make_shared<sim::PatchLibrary>(*patchGenerated_);
    auto set = doc_->patternSet();
    const sim::PatternSet patterns = set ? *set : sim::PatternSet{};
    for (std::size_t i = 0; i < recipes->size(); ++i) {
        if (Status st = setup::buildHandMadePatch(patchSession_->library, patterns, (*recipes)[i], *lib); !st)
            toolMessage(QString("Hand-made patch %1 no longer plays: %2").arg(i + 1).arg(qs(st.error().message)), true);
    }
    if (!recipes->empty()) sim::buildConnections(patchSession_->library, *lib);
    patchLibrary_ = lib;
    patchBrowser_->setPatches(patchLibrary_, &patchSession_->library);
    patchBrowser_->setRejected(rejectedPatches());
    if (!projectFile_.isEmpty()) {
        if (Status st = sim::savePatchLibrary(*patchLibrary_, patchLibraryFile(projectFile_.toStdString())); !st)
            toolMessage(qs(st.error().message), true);
    }
}

const sim::ActionLibrary* MainWindow::patchActions() const { return patchSession_ ? &patchSession_->library : nullptr; }

Result<sim::Patch> MainWindow::evaluateHandMadePatch(const setup::HandMadePatch& recipe) const {
    if (!doc_ || !patchSession_) return makeError("Generate patches first (PatternLists panel): a hand-made patch is played with the same action library");
    auto set = doc_->patternSet();
    sim::PatchLibrary one;
    if (Status st = setup::buildHandMadePatch(patchSession_->library, set ? *set : sim::PatternSet{}, recipe, one); !st) return st.error();
    return one.patches().front();
}

bool MainWindow::addHandMadePatch(const setup::HandMadePatch& recipe) {
    if (!doc_ || !patchLibrary_ || !patchSession_) {
        toolMessage("Generate patches first (PatternLists panel): a hand-made patch joins the generated library", true);
        return false;
    }
    auto played = evaluateHandMadePatch(recipe);
    if (!played) {
        toolMessage(qs(played.error().message), true);
        return false;
    }
    // It becomes the library's last patch (the generated ones, then the hand-made ones in order).
    const int index = static_cast<int>(patchLibrary_->patches().size());
    const std::string setupName = currentSetup().toStdString();
    if (Status st = doc_->addHandMadePatch(recipe, setupName, index); !st) {
        toolMessage(qs(st.error().message), true);
        return false;
    }
    rebuildPatchLibrary();
    const bool there = static_cast<int>(patchLibrary_->patches().size()) > index && patchLibrary_->patches()[static_cast<std::size_t>(index)].handMade;
    statusBar()->showMessage(QString("Hand-made patch %1 (%2, score %3) added%4")
                                 .arg(index)
                                 .arg(qs(recipe.pattern))
                                 .arg(played->score, 0, 'f', 2)
                                 .arg(setupName.empty() ? QString() : " and kept in " + qs(setupName)),
                             10000);
    if (there) patchBrowser_->selectPatch(index);
    return there;
}

void MainWindow::showHandMadeDialog() {
    if (handMade_) {
        handMade_->show();
        handMade_->raise();
        return;
    }
    handMade_ = new QDialog(this);
    handMade_->setObjectName("handMadeDialog");
    handMade_->setWindowTitle("Hand-made patch");
    auto* layout = new QVBoxLayout(handMade_);
    auto* form = new QFormLayout;
    auto* pattern = new QComboBox;
    pattern->setObjectName("handMadePattern");
    pattern->setToolTip("The PatternList the patch follows (its rules and weights score it)");
    const auto spin = [](const char* name, double lo, double hi, double value, const QString& suffix) {
        auto* s = new QDoubleSpinBox;
        s->setObjectName(name);
        s->setRange(lo, hi);
        s->setDecimals(2);
        s->setValue(value);
        s->setSuffix(suffix);
        return s;
    };
    auto* r = spin("handMadeR", 0, 10, 1.0, " m");
    r->setDecimals(3);
    auto* t1 = spin("handMadeTheta1", -180, 180, 0, " deg");
    auto* t2 = spin("handMadeTheta2", -180, 180, 180, " deg");
    auto* delay = spin("handMadeDelay", 0, 10, 0, " s");
    form->addRow("PatternList", pattern);
    form->addRow("Distance r", r);
    form->addRow("Character 1's direction to 2 (theta1)", t1);
    form->addRow("Character 2's direction to 1 (theta2)", t2);
    form->addRow("Character 2 starts after", delay);
    layout->addLayout(form);
    auto* action = new QComboBox;
    action->setObjectName("handMadeAction");
    action->setEditable(true);
    action->setInsertPolicy(QComboBox::NoInsert);
    action->setToolTip("An action of the library (type to find it)");
    auto* pick = new QHBoxLayout;
    pick->addWidget(new QLabel("Action"));
    pick->addWidget(action, 1);
    auto* add1 = new QPushButton("Add to character 1");
    add1->setObjectName("handMadeAdd1");
    auto* add2 = new QPushButton("Add to character 2");
    add2->setObjectName("handMadeAdd2");
    pick->addWidget(add1);
    pick->addWidget(add2);
    layout->addLayout(pick);
    auto* lists = new QHBoxLayout;
    auto* list1 = new QListWidget;
    list1->setObjectName("handMadeActions1");
    auto* list2 = new QListWidget;
    list2->setObjectName("handMadeActions2");
    lists->addWidget(list1);
    lists->addWidget(list2);
    layout->addLayout(lists);
    auto* result = new QLabel("Pick the actions, then Evaluate.");
    result->setObjectName("handMadeResult");
    result->setWordWrap(true);
    layout->addWidget(result);
    auto* buttons = new QHBoxLayout;
    auto* clear = new QPushButton("Clear");
    clear->setObjectName("handMadeClear");
    auto* evaluate = new QPushButton("Evaluate");
    evaluate->setObjectName("handMadeEvaluate");
    auto* keep = new QPushButton("Add as kept");
    keep->setObjectName("handMadeKeep");
    keep->setToolTip("Store the patch in the project and keep it in the current setup (one undo step)");
    buttons->addWidget(clear);
    buttons->addStretch(1);
    buttons->addWidget(evaluate);
    buttons->addWidget(keep);
    layout->addLayout(buttons);

    const auto fill = [this, pattern, action] {
        const QString was = pattern->currentText();
        pattern->clear();
        QStringList names;
        if (doc_)
            if (auto set = doc_->patternSet())
                for (const auto& p : set->patterns) names << qs(p.name);
        for (const auto& p : sim::defaultPatterns())
            if (!names.contains(qs(p.name))) names << qs(p.name);
        pattern->addItems(names);
        if (!was.isEmpty()) pattern->setCurrentText(was);
        action->clear();
        if (patchSession_)
            for (const auto& a : patchSession_->library.actions()) action->addItem(qs(a.label()));
    };
    fill();
    const auto recipe = [=] {
        setup::HandMadePatch h;
        h.pattern = pattern->currentText().toStdString();
        h.initial.r = r->value();
        h.initial.theta1 = t1->value() * kDeg;
        h.initial.theta2 = t2->value() * kDeg;
        h.initial.delay = delay->value();
        for (int i = 0; i < list1->count(); ++i) h.actions[0].push_back(list1->item(i)->text().toStdString());
        for (int i = 0; i < list2->count(); ++i) h.actions[1].push_back(list2->item(i)->text().toStdString());
        return h;
    };
    const auto addTo = [this, action, result](QListWidget* list) {
        const QString a = action->currentText().trimmed();
        if (a.isEmpty()) return;
        bool known = false;
        if (patchSession_)
            for (const auto& x : patchSession_->library.actions()) known = known || qs(x.label()) == a;
        if (!known) {
            result->setText("'" + a + "' is not an action of the library");
            toolMessage("Hand-made patch: '" + a + "' is not an action of the library", true);
            return;
        }
        list->addItem(a);
        result->setText("Pick the actions, then Evaluate.");
    };
    connect(add1, &QPushButton::clicked, handMade_, [=] { addTo(list1); });
    connect(add2, &QPushButton::clicked, handMade_, [=] { addTo(list2); });
    connect(clear, &QPushButton::clicked, handMade_, [=] {
        list1->clear();
        list2->clear();
        result->setText("Pick the actions, then Evaluate.");
    });
    connect(evaluate, &QPushButton::clicked, handMade_, [=, this] {
        auto p = evaluateHandMadePatch(recipe());
        if (!p) {
            result->setText(qs(p.error().message));
            lastError_ = qs(p.error().message);
            return;
        }
        result->setText(QString("Plays: score %1, %2 hits, %3 s").arg(p->score, 0, 'f', 2).arg(p->hits.size()).arg(p->duration, 0, 'f', 2));
    });
    connect(keep, &QPushButton::clicked, handMade_, [=, this] {
        if (addHandMadePatch(recipe())) {
            result->setText("Added to the library as kept.");
            list1->clear();
            list2->clear();
        } else {
            result->setText(lastError_);
        }
    });
    handMade_->resize(560, 480);
    handMade_->show();
}

}  // namespace fray::editor
