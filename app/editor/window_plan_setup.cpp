// MainWindow: a duel's or chase's characters in the Scene panel's Setup box
// (docs/EDITOR.md "Setup box"): the character picked, its preset, any of the
// planner's weights (sim::StyleWeights: the spec's "weights"), its takes
// ("motions"), its actions ("actions") and the reactions hits may force on it
// ("reactions"). Every change is one undo command
// (ProjectDocument::setSetupParameter), checked as simulate reads the setup;
// a refused value leaves the project as it was and says why.
#include <QComboBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QSignalBlocker>
#include <algorithm>
#include <charconv>
#include <functional>
#include <set>

#include <nlohmann/json.hpp>

#include "fray/authoring/project_document.h"
#include "fray/sim/action_catalogue.h"
#include "fray/sim/spec.h"
#include "main_window.h"

namespace fray::editor {
namespace {

using json = nlohmann::ordered_json;

QString qs(const std::string& s) { return QString::fromStdString(s); }

std::string shortest(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

// A JSON value at a pointer of the setup's spec, parsed (null when absent).
json specValue(const setup::SceneSetup& s, const std::string& pointer) {
    const auto text = setup::parameter(s, pointer);
    if (!text) return nullptr;
    json j = json::parse(*text, nullptr, false);
    return j.is_discarded() ? json(nullptr) : j;
}

// A weight's value in a StyleWeights, as the line edit shows it.
std::string weightText(const sim::StyleWeights& w, const std::string& key) {
    const auto j = nlohmann::json::parse(sim::weightsToJson(w), nullptr, false);
    if (j.is_discarded() || !j.contains(key)) return "";
    const auto& v = j[key];
    if (v.is_boolean()) return v.get<bool>() ? "true" : "false";
    return shortest(v.get<double>());
}

std::vector<std::string> strings(const json& j) {
    std::vector<std::string> out;
    if (!j.is_array()) return out;
    for (const auto& v : j)
        if (v.is_string()) out.push_back(v.get<std::string>());
    return out;
}

// Fills a check list with `items` (data and text), checked where `on` says.
// When it holds those very items already only the boxes change: the list may
// be refreshed from its own itemChanged (an edit re-reads the setup), which
// must not delete the item being toggled.
void fillCheckList(QListWidget* list, const std::vector<std::string>& items, const std::function<bool(const std::string&)>& on) {
    bool same = list->count() == static_cast<int>(items.size());
    for (int i = 0; same && i < list->count(); ++i) same = list->item(i)->data(Qt::UserRole).toString() == qs(items[static_cast<std::size_t>(i)]);
    if (!same) {
        list->clear();
        for (const auto& a : items) {
            auto* item = new QListWidgetItem(qs(a), list);
            item->setData(Qt::UserRole, qs(a));
            item->setFlags(Qt::ItemIsEnabled | Qt::ItemIsSelectable | Qt::ItemIsUserCheckable);
        }
    }
    for (int i = 0; i < list->count(); ++i) list->item(i)->setCheckState(on(items[static_cast<std::size_t>(i)]) ? Qt::Checked : Qt::Unchecked);
}

// Sets a combo box's items (text and data) unless it holds them already (as
// fillCheckList: a refresh may run from its own signal).
void fillCombo(QComboBox* combo, const std::vector<std::pair<QString, QString>>& items) {
    bool same = combo->count() == static_cast<int>(items.size());
    for (int i = 0; same && i < combo->count(); ++i)
        same = combo->itemText(i) == items[static_cast<std::size_t>(i)].first && combo->itemData(i).toString() == items[static_cast<std::size_t>(i)].second;
    if (same) return;
    combo->clear();
    for (const auto& [text, data] : items) combo->addItem(text, data);
}

QListWidget* checkList(const char* name, const char* tip) {
    auto* list = new QListWidget;
    list->setObjectName(name);
    list->setToolTip(tip);
    list->setMaximumHeight(150);
    list->setUniformItemSizes(true);
    return list;
}

}  // namespace

void MainWindow::makePlanCharacterRows() {
    planCharacter_ = new QComboBox;
    planCharacter_->setObjectName("plan_character");
    planCharacter_->setToolTip("The character whose preset, weights, takes and actions the rows below edit");
    connect(planCharacter_, &QComboBox::currentIndexChanged, this, [this] {
        if (!fillingParams_) refreshSetupParameters();
    });
    planPreset_ = new QComboBox;
    planPreset_->setObjectName("plan_preset");
    planPreset_->setToolTip("The character's planner preset: the project's presets (fray-cli presets); its weights apply unless set below");
    connect(planPreset_, &QComboBox::currentIndexChanged, this, [this] {
        if (fillingParams_ || planCharacter_->currentIndex() < 0 || planPreset_->currentIndex() < 0) return;
        const std::string name = planPreset_->currentData().toString().toStdString();
        setGraphParameter("characters/" + std::to_string(planCharacter_->currentIndex()) + "/preset", json(name).dump());
    });
    auto* weightRow = new QWidget;
    weightRow->setObjectName("plan_weightRow");
    auto* h = new QHBoxLayout(weightRow);
    h->setContentsMargins(0, 0, 0, 0);
    planWeightKey_ = new QComboBox;
    planWeightKey_->setObjectName("plan_weightKey");
    planWeightKey_->setToolTip("Which of the planner's weights (competitive, cooperative, path, pruning ranges; docs/SIM.md)");
    for (const auto& k : sim::weightKeys()) planWeightKey_->addItem(qs(k));
    connect(planWeightKey_, &QComboBox::currentIndexChanged, this, [this] {
        if (!fillingParams_) refreshSetupParameters();
    });
    planWeight_ = new QLineEdit;
    planWeight_->setObjectName("plan_weight");
    planWeight_->setToolTip("The weight's value for this character (a number; true or false for a switch); "
                            "empty: the preset's value again. Enter sets it (one undo step)");
    connect(planWeight_, &QLineEdit::editingFinished, this, [this] { setPlanWeight(); });
    planWeightFrom_ = new QLabel;
    planWeightFrom_->setObjectName("plan_weightFrom");
    h->addWidget(planWeightKey_, 2);
    h->addWidget(planWeight_, 2);
    h->addWidget(planWeightFrom_, 1);
    planMotions_ = checkList("plan_motions", "The takes the character's actions come from (the spec's \"motions\"); all checked: every take");
    planActions_ = checkList("plan_actions",
                             "The actions the character may choose, by annotation (the spec's \"actions\"; reactions are forced by hits)");
    planReactions_ = checkList("plan_reactions",
                               "The reactions a hit may force on the character, by annotation (the spec's \"reactions\"; "
                               "all checked: every reaction of its takes)");
    planReactions_->setMaximumHeight(80);  // a few reactions (pushed, falling)
    connect(planMotions_, &QListWidget::itemChanged, this, [this] { setPlanList(planMotions_, "motions"); });
    connect(planActions_, &QListWidget::itemChanged, this, [this] { setPlanList(planActions_, "actions"); });
    connect(planReactions_, &QListWidget::itemChanged, this, [this] { setPlanList(planReactions_, "reactions"); });
    paramsForm_->addRow("Character", planCharacter_);
    paramsForm_->addRow("Preset", planPreset_);
    paramsForm_->addRow("Weight", weightRow);
    paramsForm_->addRow("Takes", planMotions_);
    paramsForm_->addRow("Actions", planActions_);
    paramsForm_->addRow("Reactions", planReactions_);
    planRows_ = {planCharacter_, planPreset_, weightRow, planMotions_, planActions_, planReactions_};
}

void MainWindow::setPlanWeight() {
    if (fillingParams_ || !doc_ || currentSetup().isEmpty() || planCharacter_->currentIndex() < 0) return;
    const QString text = planWeight_->text().trimmed();
    if (text == planWeight_->property("shown").toString()) return;  // Enter again, or focus left unchanged
    const std::string key = planWeightKey_->currentText().toStdString();
    const std::string who = planCharacter_->currentText().toStdString();
    const std::string pointer = "characters/" + std::to_string(planCharacter_->currentIndex()) + "/weights/" + key;
    if (text.isEmpty()) {
        setGraphParameter(pointer, "null");  // back to the preset's value
        return;
    }
    sim::StyleWeights check;
    if (auto st = sim::applyWeightEdit(check, key + "=" + text.toStdString()); !st) {
        toolMessage(QString("Setup '%1', %2's weight: %3").arg(currentSetup(), qs(who), qs(st.error().message)), true);
        refreshSetupParameters();
        return;
    }
    std::string value = text.toStdString();
    if (value != "true" && value != "false") {
        double x = 0;
        std::from_chars(value.data(), value.data() + value.size(), x);
        value = shortest(x);
    }
    setGraphParameter(pointer, value);
}

void MainWindow::setPlanList(QListWidget* list, const char* field) {
    if (fillingParams_ || !doc_ || currentSetup().isEmpty() || planCharacter_->currentIndex() < 0) return;
    // The stored order is kept: what stays checked, then what was checked now.
    const std::string pointer = "characters/" + std::to_string(planCharacter_->currentIndex()) + "/" + field;
    std::vector<std::string> on;
    for (int i = 0; i < list->count(); ++i)
        if (list->item(i)->checkState() == Qt::Checked) on.push_back(list->item(i)->data(Qt::UserRole).toString().toStdString());
    std::vector<std::string> stored;
    if (auto s = doc_->sceneSetup(currentSetup().toStdString())) stored = strings(specValue(*s, "/" + pointer));
    json checked = json::array();
    for (const auto& x : stored)
        if (std::find(on.begin(), on.end(), x) != on.end()) checked.push_back(x);
    for (const auto& x : on)
        if (std::find(stored.begin(), stored.end(), x) == stored.end()) checked.push_back(x);
    if (checked.empty()) {
        const std::string_view f(field);
        toolMessage(QString("Setup '%1': %2 needs at least one %3")
                        .arg(currentSetup(), planCharacter_->currentText(), f == "motions" ? "take" : f == "actions" ? "action" : "reaction"),
                    true);
        refreshSetupParameters();
        return;
    }
    setGraphParameter(pointer, checked.dump());
}

void MainWindow::refreshPlanCharacterRows(const setup::SceneSetup* s) {
    const std::vector<setup::SetupCharacter> people = s ? setup::characters(*s) : std::vector<setup::SetupCharacter>{};
    const bool shown = s && setup::isTreeExpansion(s->kind) && !people.empty();
    for (QWidget* w : planRows_) paramsForm_->setRowVisible(w, shown);
    if (!shown || !doc_) return;
    const QSignalBlocker q1(planCharacter_), q2(planPreset_), q3(planWeightKey_), q4(planMotions_), q5(planActions_), q6(planReactions_);
    // The character picked stays picked (by index) while the setup has it.
    int c = planCharacter_->currentIndex();
    if (planCharacter_->property("setup").toString() != qs(s->name)) c = 0;
    planCharacter_->setProperty("setup", qs(s->name));
    std::vector<std::pair<QString, QString>> names;
    for (const auto& p : people) names.emplace_back(qs(p.name), qs(p.name));
    fillCombo(planCharacter_, names);
    c = std::clamp(c, 0, static_cast<int>(people.size()) - 1);
    planCharacter_->setCurrentIndex(c);
    const std::string at = "/characters/" + std::to_string(c);

    // Preset: the project's presets (built-in and the project's own).
    const std::string file = doc_->filePath().empty() ? doc_->project().name : doc_->filePath().string();
    const auto presets = sim::projectPresets(doc_->project(), file);
    const json presetJ = specValue(*s, at + "/preset");
    const std::string preset = presetJ.is_string() ? presetJ.get<std::string>() : "general-boxer";
    sim::StyleWeights base;
    std::vector<std::pair<QString, QString>> presetItems;
    bool known = false;
    if (presets) {
        for (const auto& p : *presets) {
            presetItems.emplace_back(qs(p.name), qs(p.name));
            if (p.name == preset) base = p.weights, known = true;
        }
    }
    if (!known) presetItems.emplace_back(qs(preset) + " (unknown)", qs(preset));
    fillCombo(planPreset_, presetItems);
    if (presets)
        for (std::size_t i = 0; i < presets->size(); ++i) planPreset_->setItemData(static_cast<int>(i), qs((*presets)[i].description), Qt::ToolTipRole);
    planPreset_->setCurrentIndex(planPreset_->findData(qs(preset)));

    // The weight: the setup's value when it sets one, else the preset's.
    const std::string key = planWeightKey_->currentText().toStdString();
    const json own = specValue(*s, at + "/weights/" + key);
    std::string shown2;
    if (own.is_boolean()) shown2 = own.get<bool>() ? "true" : "false";
    else if (own.is_number()) shown2 = shortest(own.get<double>());
    else shown2 = weightText(base, key);
    planWeight_->setText(qs(shown2));
    planWeight_->setProperty("shown", qs(shown2));
    planWeightFrom_->setText(own.is_null() ? "preset" : "set here");
    planWeightFrom_->setToolTip(own.is_null() ? QString("%1's value (%2)").arg(qs(preset), qs(shown2))
                                              : QString("Set in this setup; %1's value is %2").arg(qs(preset), qs(weightText(base, key))));

    // Takes: every take of the project; checked as the setup stores them (none stored: all).
    const prep::Project& project = doc_->project();
    const std::vector<std::string> motions = strings(specValue(*s, at + "/motions"));
    std::vector<std::string> takeIds;
    for (const auto& m : project.motions) takeIds.push_back(m.id);
    fillCheckList(planMotions_, takeIds, [&](const std::string& id) {
        return motions.empty() || std::find(motions.begin(), motions.end(), id) != motions.end();
    });
    // Actions: "@word" for each annotation a chosen take's own actions carry
    // (reactions aside), then what the setup stores beyond them (action names).
    std::set<std::string> words;
    for (const auto& m : project.motions) {
        if (!motions.empty() && std::find(motions.begin(), motions.end(), m.id) == motions.end()) continue;
        for (const auto& a : m.actions.actions)
            if (!(sim::actionFlags(a.annotations) & sim::kReactive)) words.insert(a.annotations.begin(), a.annotations.end());
    }
    // A check list of "@word" for the project's words in `found` (in the
    // vocabulary's order), then what the setup stores at `field` beyond them;
    // all checked while the setup stores no list.
    const auto fillWords = [&](QListWidget* list, const std::set<std::string>& found, const char* field) {
        const json storedJ = specValue(*s, at + field);
        const std::vector<std::string> stored = strings(storedJ);
        std::vector<std::string> items;
        for (const auto& w : project.vocabulary)
            if (found.contains(w)) items.push_back("@" + w);
        for (const auto& a : stored)
            if (std::find(items.begin(), items.end(), a) == items.end()) items.push_back(a);
        fillCheckList(list, items, [&](const std::string& a) {
            return storedJ.is_null() || std::find(stored.begin(), stored.end(), a) != stored.end();
        });
    };
    fillWords(planActions_, words, "/actions");
    // Reactions: "@word" for each annotation of a reaction (pushed, falling...)
    // in the chosen takes, or in any take when they hold none (as simulate
    // falls back), then what the setup stores beyond them.
    std::set<std::string> reactive;
    for (int pass = 0; pass < 2 && reactive.empty(); ++pass) {
        for (const auto& m : project.motions) {
            if (pass == 0 && !motions.empty() && std::find(motions.begin(), motions.end(), m.id) == motions.end()) continue;
            for (const auto& a : m.actions.actions) {
                if (!(sim::actionFlags(a.annotations) & sim::kReactive)) continue;
                for (const auto& w : a.annotations)
                    if (sim::actionFlags({w}) & sim::kReactive) reactive.insert(w);
            }
        }
    }
    fillWords(planReactions_, reactive, "/reactions");
}

}  // namespace fray::editor
