// MainWindow: new setups of any kind and the parameters of the Interaction
// Graph kinds (graph-duel, graph-teams, graph-carry) in the Scene panel
// (docs/EDITOR.md "Interaction Graph setups"). Every parameter edit is one
// undo command (ProjectDocument::setSetupParameter), checked as it is made;
// Generate runs them through pipeline::runSetup like any setup.
#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QInputDialog>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QSignalBlocker>
#include <QSpinBox>
#include <QVBoxLayout>
#include <charconv>
#include <optional>
#include <vector>

#include "fray/authoring/project_document.h"
#include "fray/igraph/carry.h"
#include "fray/setup/graph_setup.h"
#include "main_window.h"

namespace fray::editor {
namespace {

using setup::SetupKind;

QString qs(const std::string& s) { return QString::fromStdString(s); }

// A number as JSON text, the shortest spelling that reads back the same.
std::string jsonNumber(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

enum class FieldType { Int, Double, Choice, Bool };
struct Field {
    const char* key;    // JSON pointer without the leading '/'
    const char* label;
    FieldType type;
    double lo, hi, step;
    const char* choices;  // Choice: '|'-separated
    bool duel, teams, carry;
    const char* tip;
};

constexpr Field kFields[] = {
    {"duration", "Duration (s)", FieldType::Double, 0.1, 3600, 1, "", true, true, true, "How long the scene lasts"},
    {"seed", "Seed", FieldType::Int, 0, 2147483647, 1, "", true, true, true,
     "Start placements and the match (duel, teams); the carry graph's sampling and the run (carry)"},
    {"you", "Red boxer (you)", FieldType::Choice, 0, 0, 0, "graph|static", true, false, false,
     "graph: driven by the graph's policy; static: a static target (idles and guards, never attacks)"},
    {"style", "Red style", FieldType::Choice, 0, 0, 0, "general|infighter|outboxer", true, true, false, "Boxing style of red's policy"},
    {"depth", "Depth", FieldType::Int, 1, 64, 1, "", true, true, true, "Min-max depth of red's policy (carry: of the 8 direction policies)"},
    {"opponent", "Blue boxer", FieldType::Choice, 0, 0, 0, "graph|static", true, false, false,
     "graph: a second graph boxer; static: a static target"},
    {"opponent_style", "Blue style", FieldType::Choice, 0, 0, 0, "general|infighter|outboxer", true, true, false, "Boxing style of blue's policy"},
    {"opponent_depth", "Blue depth", FieldType::Int, 1, 64, 1, "", true, true, false, "Min-max depth of blue's policy"},
    {"red", "Red team", FieldType::Int, 1, 5000, 1, "", false, true, false, "Characters on the red side"},
    {"blue", "Blue team", FieldType::Int, 1, 5000, 1, "", false, true, false, "Characters on the blue side"},
    {"distance", "Distance (m)", FieldType::Double, 0.5, 10, 0.1, "", true, false, false, "The boxers' start distance"},
    {"jitter", "Jitter", FieldType::Double, 0, 2, 0.05, "", true, true, false, "Seeded placement jitter: metres, and degrees / 20"},
    {"refine", "Refined look-ups", FieldType::Bool, 0, 0, 0, "", true, true, false,
     "Graph boxers re-simulate their state's edges from the real bodies (slower; docs/IGRAPH.md)"},
    {"graph_states", "Graph states", FieldType::Int, 16, 10000000, 1000, "", true, true, false,
     "Size of a graph built in memory when the project has no valid graph file beside it (P.frayproj.igraph)"},
    {"carry_states", "Carry graph states", FieldType::Int, 16, 1000000, 1000, "", false, false, true, "Size of the carry graph (built in memory)"},
    {"weights/w_theta", "w_theta", FieldType::Double, 0, 1e6, 0.5, "", false, false, true, "Reward weight of the carriers' facing angles"},
    {"weights/w_d", "w_d", FieldType::Double, 0, 1e6, 10, "", false, false, true, "Reward weight of the grip-distance error"},
    {"weights/w_v", "w_v", FieldType::Double, 0, 1e6, 1, "", false, false, true, "Reward weight of the box's velocity error"},
    {"weights/speed", "Speed (m/s)", FieldType::Double, 0, 10, 0.05, "", false, false, true, "The box's desired speed along the path"},
    {"weights/gamma", "gamma", FieldType::Double, 0, 1, 0.05, "", false, false, true, "Discount of the carry policies"},
};

// Tree-expansion setups (duel, chase): the scene's length and seed and each
// character's search depth, at their places in the setup's spec. A row shows
// when the setup has the field (a character's row names it).
constexpr int kPlanCharacters = 4;
constexpr Field kPlanFields[] = {
    {"duration", "Duration (s)", FieldType::Double, 0.1, 3600, 1, "", false, false, false, "How long the scene lasts"},
    {"seed", "Seed", FieldType::Int, 0, 2147483647, 1, "", false, false, false, "The planner's random choices among equal options"},
    {"characters/0/depth", "Depth", FieldType::Int, 1, 10, 1, "", false, false, false, "How many decisions ahead this character plans"},
    {"characters/1/depth", "Depth", FieldType::Int, 1, 10, 1, "", false, false, false, "How many decisions ahead this character plans"},
    {"characters/2/depth", "Depth", FieldType::Int, 1, 10, 1, "", false, false, false, "How many decisions ahead this character plans"},
    {"characters/3/depth", "Depth", FieldType::Int, 1, 10, 1, "", false, false, false, "How many decisions ahead this character plans"},
};
static_assert(std::size(kPlanFields) == 2 + kPlanCharacters);

// Interaction Patches kinds: the scalar parameters of their specs (ranges as
// fray-cli compose reads them). A row shows when the setup has the field.
constexpr Field kComposeFields[] = {
    {"duration", "Duration (s)", FieldType::Double, 0.1, 3600, 1, "", false, false, false, "How long the scene lasts"},
    {"seed", "Seed", FieldType::Int, 0, 2147483647, 1, "", false, false, false, "The composer's random choices"},
    {"entry_radius", "Entry radius (m)", FieldType::Double, 0, 1000, 0.5, "", false, false, false, "How far away characters enter"},
    {"enemies", "Enemies", FieldType::Int, 1, 1000, 1, "", false, false, false, "Enemies around the main character (one-vs-many)"},
    {"porters", "Porters", FieldType::Int, 2, 100, 1, "", false, false, false, "People passing the luggage along"},
    {"handoffs", "Handoffs", FieldType::Int, 1, 10000, 1, "", false, false, false, "How many times the luggage changes hands"},
    {"tacklers", "Tacklers", FieldType::Int, 1, 1000, 1, "", false, false, false, "Defenders tackling the runner (football)"},
    {"goal", "Goal (m)", FieldType::Double, 0, 1000, 1, "", false, false, false, "How far the runner's goal line is"},
    {"background", "Background people", FieldType::Int, 0, 10000, 1, "", false, false, false,
     "People standing outside the painted area (domino)"},
    {"max_characters", "Max characters", FieldType::Int, 1, 100000, 10, "", false, false, false, "At most this many people (domino)"},
    {"crowd", "Crowd", FieldType::Int, 1, 20000, 1, "", false, false, false, "People in the crowd the rat runs through"},
};

// The rat kind's nested and own numbers: a row for each whether the setup
// stores it or not (the value compose uses when absent, sim::RatSpec's
// defaults); ranges as compose reads them.
struct RatField {
    const char* key;
    const char* label;
    double lo, hi, step, def;
    const char* tip;
};
constexpr RatField kRatFields[] = {
    {"rat/speed", "Rat speed (m/s)", 0.3, 10, 0.1, 2.5, "How fast the rat runs along its trajectory (its run patches are made for it)"},
    {"rat/start", "Rat start (s)", 0, 600, 0.5, 1.0, "When the rat starts running"},
    {"band", "Band (m)", 0, 100, 0.5, 2.5, "How far either side of the rat's trajectory the crowd stands"},
    {"spacing", "Spacing (m)", 0.5, 20, 0.1, 0.9, "How far apart the people of the crowd stand"},
    {"reach", "Reach (m)", 0, 10, 0.1, 1.0, "How near the rat passes for someone to step out of its way"},
    {"bumps", "Bumps", 0, 1, 0.05, 0.5, "0: people stepping aside avoid bumping into their neighbours; 1: they seek it"},
};

// A plan field's value from the setup's spec, when it is a number there.
std::optional<double> planValue(const setup::SceneSetup& s, const std::string& key) {
    const auto text = setup::parameter(s, "/" + key);
    if (!text) return std::nullopt;
    double v = 0;
    const auto r = std::from_chars(text->data(), text->data() + text->size(), v);
    if (r.ec != std::errc() || r.ptr != text->data() + text->size()) return std::nullopt;
    return v;
}

bool fieldOf(const Field& f, SetupKind k) {
    return (k == SetupKind::GraphDuel && f.duel) || (k == SetupKind::GraphTeams && f.teams) || (k == SetupKind::GraphCarry && f.carry);
}

QString objectNameOf(const Field& f) { return "param_" + QString(f.key).replace('/', '_'); }

// The value a field shows: the parameter read by graphParams (its default when absent).
double valueOf(const setup::GraphSetupParams& p, const std::string& key) {
    if (key == "duration") return p.duration;
    if (key == "seed") return static_cast<double>(p.seed);
    if (key == "depth") return p.depth;
    if (key == "opponent_depth") return p.opponentDepth;
    if (key == "red") return p.red;
    if (key == "blue") return p.blue;
    if (key == "distance") return p.distance;
    if (key == "jitter") return p.jitter;
    if (key == "refine") return p.refine ? 1 : 0;
    if (key == "graph_states") return static_cast<double>(p.graphStates);
    if (key == "carry_states") return static_cast<double>(p.carryStates);
    if (key.starts_with("weights/")) {
        const std::string name = key.substr(8);
        for (const auto& [n, v] : p.carryWeights)
            if (n == name) return v;
        const igraph::CarryWeights w;
        if (name == "w_theta") return w.wTheta;
        if (name == "w_d") return w.wD;
        if (name == "w_v") return w.wV;
        if (name == "speed") return w.speed;
        return w.gamma;
    }
    return 0;
}
std::string choiceOf(const setup::GraphSetupParams& p, const std::string& key) {
    if (key == "you") return p.you;
    if (key == "opponent") return p.opponent;
    if (key == "style") return p.style;
    return p.opponentStyle;
}

const char* kindTitle(SetupKind k) {
    switch (k) {
    case SetupKind::Duel: return "duel (tree expansion)";
    case SetupKind::Chase: return "chase (tree expansion)";
    case SetupKind::OneVsMany: return "one-vs-many (patches)";
    case SetupKind::OneVsOne: return "one-vs-one (patches)";
    case SetupKind::Domino: return "domino (patches)";
    case SetupKind::Luggage: return "luggage (patches)";
    case SetupKind::Football: return "football (patches)";
    case SetupKind::Rat: return "rat (patches)";
    case SetupKind::GraphDuel: return "graph-duel (Interaction Graph)";
    case SetupKind::GraphTeams: return "graph-teams (Interaction Graph)";
    case SetupKind::GraphCarry: return "graph-carry (Interaction Graph)";
    }
    return "";
}

}  // namespace

QWidget* MainWindow::makeSetupParameters() {
    auto* box = new QGroupBox("Setup");
    box->setObjectName("setupBox");
    auto* v = new QVBoxLayout(box);
    v->setContentsMargins(4, 4, 4, 4);
    auto* row = new QHBoxLayout;
    newKind_ = new QComboBox;
    newKind_->setObjectName("sceneNewKind");
    newKind_->setToolTip("The kind of a new setup: tree expansion, Interaction Patches or the Interaction Graph");
    for (SetupKind k : setup::allSetupKinds()) newKind_->addItem(kindTitle(k), QString(setup::setupKindName(k)));
    auto* add = new QPushButton("New setup");
    add->setObjectName("sceneNewSetup");
    add->setToolTip("Add a setup of the chosen kind with its demo parameters (one undo step) and select it");
    connect(add, &QPushButton::clicked, this, [this] {
        const auto kind = setup::setupKindFromName(newKind_->currentData().toString().toStdString());
        if (!kind) return;
        QString name = newSetupName(*kind);
        if (!options_.noDialogs) {
            bool ok = false;
            name = QInputDialog::getText(this, "New setup", "Setup name", QLineEdit::Normal, name, &ok).trimmed();
            if (!ok || name.isEmpty()) return;
        }
        newSetup(name, *kind);
    });
    row->addWidget(newKind_, 1);
    row->addWidget(add);
    v->addLayout(row);
    paramsForm_ = new QFormLayout;
    paramsForm_->setContentsMargins(0, 0, 0, 0);
    auto fields = std::vector<const Field*>();
    for (const Field& f : kFields) fields.push_back(&f);
    for (const Field& f : kPlanFields) fields.push_back(&f);
    for (const Field& f : kComposeFields) fields.push_back(&f);
    for (const Field* field : fields) {
        const Field& f = *field;
        QWidget* w = nullptr;
        const std::string key = f.key;
        switch (f.type) {
        case FieldType::Int: {
            auto* s = new QSpinBox;
            s->setRange(static_cast<int>(f.lo), static_cast<int>(f.hi));
            s->setSingleStep(static_cast<int>(f.step));
            s->setKeyboardTracking(false);
            connect(s, &QSpinBox::valueChanged, this, [this, key](int x) { setGraphParameter(key, std::to_string(x)); });
            w = s;
            break;
        }
        case FieldType::Double: {
            auto* s = new QDoubleSpinBox;
            s->setRange(f.lo, f.hi);
            s->setSingleStep(f.step);
            s->setDecimals(3);
            s->setKeyboardTracking(false);
            connect(s, &QDoubleSpinBox::valueChanged, this, [this, key](double x) { setGraphParameter(key, jsonNumber(x)); });
            w = s;
            break;
        }
        case FieldType::Choice: {
            auto* c = new QComboBox;
            for (const QString& item : QString(f.choices).split('|')) c->addItem(item);
            connect(c, &QComboBox::currentTextChanged, this, [this, key](const QString& t) { setGraphParameter(key, "\"" + t.toStdString() + "\""); });
            w = c;
            break;
        }
        case FieldType::Bool: {
            auto* c = new QCheckBox;
            connect(c, &QCheckBox::toggled, this, [this, key](bool on) { setGraphParameter(key, on ? "true" : "false"); });
            w = c;
            break;
        }
        }
        // The plan fields share keys with the graph fields: "plan_duration" beside "param_duration".
        const bool planField = field >= std::begin(kPlanFields) && field < std::end(kPlanFields);
        const bool composeField = field >= std::begin(kComposeFields) && field < std::end(kComposeFields);
        w->setObjectName(planField ? "plan_" + objectNameOf(f).mid(6) : composeField ? "compose_" + objectNameOf(f).mid(6) : objectNameOf(f));
        w->setToolTip(f.tip);
        paramsForm_->addRow(f.label, w);
        paramWidgets_.push_back(w);
        // A duel's or chase's characters after its duration, seed and depths.
        if (field == &kPlanFields[std::size(kPlanFields) - 1]) makePlanCharacterRows();
    }
    for (const RatField& f : kRatFields) {
        auto* s = new QDoubleSpinBox;
        s->setRange(f.lo, f.hi);
        s->setSingleStep(f.step);
        s->setDecimals(3);
        s->setKeyboardTracking(false);
        const std::string key = f.key;
        connect(s, &QDoubleSpinBox::valueChanged, this, [this, key](double x) { setGraphParameter(key, jsonNumber(x)); });
        s->setObjectName("compose_" + QString(f.key).replace('/', '_'));
        s->setToolTip(f.tip);
        paramsForm_->addRow(f.label, s);
        paramWidgets_.push_back(s);
    }
    // A domino setup's painted floor: its scale (the pixels stay, the floor grows from its origin).
    floorScale_ = new QDoubleSpinBox;
    floorScale_->setObjectName("compose_floor_metres_per_pixel");
    floorScale_->setToolTip("Metres per pixel of the painted floor, in (0.001, 10] (one undo step); pixel (0, 0) stays at the "
                            "floor's origin, so the painting grows or shrinks away from that corner; chain starts stay on their pixels");
    floorScale_->setRange(0.001, 10);
    floorScale_->setDecimals(4);
    floorScale_->setSingleStep(0.01);
    floorScale_->setKeyboardTracking(false);
    connect(floorScale_, &QDoubleSpinBox::valueChanged, this, [this](double x) {
        if (fillingParams_ || !doc_ || currentSetup().isEmpty()) return;
        if (Status st = doc_->setFloorScale(currentSetup().toStdString(), x); !st) {
            toolMessage(qs(st.error().message), true);
            refreshSetupParameters();
        }
    });
    paramsForm_->addRow("Floor scale (m/px)", floorScale_);
    paramWidgets_.push_back(floorScale_);
    v->addLayout(paramsForm_);
    paramsInfo_ = new QLabel;
    paramsInfo_->setObjectName("setupParamsInfo");
    paramsInfo_->setWordWrap(true);
    v->addWidget(paramsInfo_);
    refreshSetupParameters();
    return box;
}

QString MainWindow::newSetupName(setup::SetupKind kind) const {
    const QString base = setup::setupKindName(kind);
    auto setups = doc_ ? doc_->setups() : Result<std::vector<setup::SceneSetup>>(std::vector<setup::SceneSetup>{});
    for (int n = 1;; ++n) {
        const QString name = n == 1 ? base : QString("%1 %2").arg(base).arg(n);
        if (!setups || !setup::findSetup(*setups, name.toStdString())) return name;
    }
}

bool MainWindow::newSetup(const QString& name, setup::SetupKind kind) {
    if (!doc_) {
        toolMessage("Open a project to add a setup to it", true);
        return false;
    }
    if (Status st = doc_->addSetup(name.toStdString(), kind); !st) {
        showError("New setup", qs(st.error().message));
        return false;
    }
    fillSceneSources();
    const bool ok = selectSetup(name);
    // A carry setup's path is drawn for the box: the trajectory tools draw for it.
    if (kind == SetupKind::GraphCarry) selectToolCharacter(setup::kCarryPathCharacter);
    return ok;
}

void MainWindow::setGraphParameter(const std::string& key, const std::string& json) {
    if (fillingParams_ || !doc_ || currentSetup().isEmpty()) return;
    if (Status st = doc_->setSetupParameter(currentSetup().toStdString(), "/" + key, json); !st) {
        toolMessage(qs(st.error().message), true);
        refreshSetupParameters();  // the widget shows the stored value again
    }
}

void MainWindow::refreshSetupParameters() {
    if (!paramsForm_) return;
    fillingParams_ = true;
    std::optional<setup::SceneSetup> s;
    if (doc_ && !currentSetup().isEmpty()) {
        if (auto r = doc_->sceneSetup(currentSetup().toStdString())) s = std::move(*r);
    }
    const bool graph = s && setup::isGraphKind(s->kind);
    Result<setup::GraphSetupParams> p = graph ? setup::graphParams(*s, false) : Result<setup::GraphSetupParams>(setup::GraphSetupParams{});
    for (std::size_t i = 0; i < std::size(kFields); ++i) {
        const Field& f = kFields[i];
        QWidget* w = paramWidgets_[i];
        const bool shown = graph && fieldOf(f, s->kind);
        paramsForm_->setRowVisible(w, shown);
        if (!shown || !p) continue;
        const QSignalBlocker quiet(w);
        switch (f.type) {
        case FieldType::Int: static_cast<QSpinBox*>(w)->setValue(static_cast<int>(valueOf(*p, f.key))); break;
        case FieldType::Double: static_cast<QDoubleSpinBox*>(w)->setValue(valueOf(*p, f.key)); break;
        case FieldType::Choice: static_cast<QComboBox*>(w)->setCurrentText(qs(choiceOf(*p, f.key))); break;
        case FieldType::Bool: static_cast<QCheckBox*>(w)->setChecked(valueOf(*p, f.key) != 0); break;
        }
    }
    const bool plan = s && setup::isTreeExpansion(s->kind);
    for (std::size_t i = 0; i < std::size(kPlanFields); ++i) {
        const Field& f = kPlanFields[i];
        QWidget* w = paramWidgets_[std::size(kFields) + i];
        const std::optional<double> v = plan ? planValue(*s, f.key) : std::nullopt;
        paramsForm_->setRowVisible(w, v.has_value());
        if (!v) continue;
        if (i >= 2) {
            // "Depth: red"
            const auto name = setup::parameter(*s, "/characters/" + std::to_string(i - 2) + "/name");
            QString who = name && name->size() >= 2 ? qs(name->substr(1, name->size() - 2)) : QString("character %1").arg(i - 2);
            if (auto* label = qobject_cast<QLabel*>(paramsForm_->labelForField(w))) label->setText("Depth: " + who);
        }
        const QSignalBlocker quiet(w);
        if (f.type == FieldType::Int) static_cast<QSpinBox*>(w)->setValue(static_cast<int>(*v));
        else static_cast<QDoubleSpinBox*>(w)->setValue(*v);
    }
    refreshPlanCharacterRows(plan ? &*s : nullptr);
    const bool compose = s && !plan && !graph;
    for (std::size_t i = 0; i < std::size(kComposeFields); ++i) {
        const Field& f = kComposeFields[i];
        QWidget* w = paramWidgets_[std::size(kFields) + std::size(kPlanFields) + i];
        const std::optional<double> v = compose ? planValue(*s, f.key) : std::nullopt;
        paramsForm_->setRowVisible(w, v.has_value());
        if (!v) continue;
        const QSignalBlocker quiet(w);
        if (f.type == FieldType::Int) static_cast<QSpinBox*>(w)->setValue(static_cast<int>(*v));
        else static_cast<QDoubleSpinBox*>(w)->setValue(*v);
    }
    const bool rat = compose && s->kind == SetupKind::Rat;
    for (std::size_t i = 0; i < std::size(kRatFields); ++i) {
        const RatField& f = kRatFields[i];
        auto* w = static_cast<QDoubleSpinBox*>(paramWidgets_[std::size(kFields) + std::size(kPlanFields) + std::size(kComposeFields) + i]);
        paramsForm_->setRowVisible(w, rat);
        if (!rat) continue;
        const QSignalBlocker quiet(w);
        w->setValue(planValue(*s, f.key).value_or(f.def));
    }
    const bool floor = compose && s->floor.has_value();
    paramsForm_->setRowVisible(floorScale_, floor);
    if (floor) {
        const QSignalBlocker quiet(floorScale_);
        floorScale_->setValue(s->floor->metresPerPixel);
    }
    if (!s) paramsInfo_->setText("No setup selected: pick one above, or a kind and New setup.");
    else if (plan)
        paramsInfo_->setText(QString("%1 setup planned by tree expansion: each character's preset, weights, takes, actions and reactions above; paths, "
                                     "checkpoints and starts on the floor (Floor tools), pins in the action track.")
                                 .arg(setup::setupKindName(s->kind)));
    else if (!graph) paramsInfo_->setText(QString("%1 setup: its numbers above, the rest on the floor (Floor tools) or with fray-cli setup.").arg(setup::setupKindName(s->kind)));
    else if (!p) paramsInfo_->setText("The parameters cannot be read: " + qs(p.error().message));
    else if (s->kind == SetupKind::GraphCarry)
        paramsInfo_->setText(setup::carryTrajectory(*s) ? "Two carriers of a long box follow the box's path (trajectory of 'box': redraw it with "
                                                          "the Polyline, Arc or Circle tool)."
                                                        : "Draw the box's path: the Polyline, Arc or Circle tool, character 'box'.");
    else
        paramsInfo_->setText("Driven by the Interaction Graph: the graph file beside the project when valid (fray-cli igraph build), "
                             "else built in memory (Graph states) on the first Generate.");
    fillingParams_ = false;
}

}  // namespace fray::editor
