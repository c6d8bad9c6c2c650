#include "inspector_panel.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QPushButton>
#include <QScrollArea>
#include <QToolButton>
#include <QVBoxLayout>
#include <algorithm>
#include <numbers>

#include "fray/authoring/project_document.h"

namespace fray::editor {

namespace {

constexpr double kDegrees = 180.0 / std::numbers::pi;

QString qs(const std::string& s) { return QString::fromStdString(s); }
std::string ss(const QString& s) { return s.trimmed().toStdString(); }

void clearLayout(QWidget* w) {
    for (QObject* child : w->children())
        if (auto* widget = qobject_cast<QWidget*>(child)) {
            widget->hide();
            widget->deleteLater();
        }
}

}  // namespace

InspectorPanel::InspectorPanel(QWidget* parent) : QWidget(parent) {
    auto* outer = new QVBoxLayout(this);
    outer->setContentsMargins(4, 4, 4, 4);
    title_ = new QLabel;
    title_->setObjectName("inspectorTitle");
    QFont big = title_->font();
    big.setBold(true);
    big.setPointSizeF(big.pointSizeF() * 1.25);
    title_->setFont(big);
    title_->setWordWrap(true);
    contextLabel_ = new QLabel;
    contextLabel_->setObjectName("inspectorContext");
    contextLabel_->setWordWrap(true);
    outer->addWidget(title_);
    outer->addWidget(contextLabel_);

    body_ = new QWidget;
    auto* form = new QFormLayout(body_);
    form->setContentsMargins(0, 6, 0, 0);
    name_ = new QLineEdit;
    name_->setObjectName("actionName");
    name_->setPlaceholderText("unnamed (e.g. jab)");
    form->addRow("Name", name_);

    chips_ = new QWidget;
    chips_->setObjectName("annotationChips");
    auto* chipsLayout = new QGridLayout(chips_);
    chipsLayout->setContentsMargins(0, 0, 0, 0);
    addAnnotation_ = new QComboBox;
    addAnnotation_->setObjectName("addAnnotation");
    addAnnotation_->setEditable(true);
    addAnnotation_->setInsertPolicy(QComboBox::NoInsert);
    addAnnotation_->lineEdit()->setPlaceholderText("add an annotation...");
    auto* annotations = new QWidget;
    auto* annotationsLayout = new QVBoxLayout(annotations);
    annotationsLayout->setContentsMargins(0, 0, 0, 0);
    annotationsLayout->addWidget(chips_);
    annotationsLayout->addWidget(addAnnotation_);
    form->addRow("Annotations", annotations);

    proposals_ = new QWidget;
    proposals_->setObjectName("proposals");
    auto* proposalsLayout = new QGridLayout(proposals_);
    proposalsLayout->setContentsMargins(0, 0, 0, 0);
    form->addRow("Proposals", proposals_);

    jointList_ = new QListWidget;
    jointList_->setObjectName("jointsUsed");
    jointList_->setMaximumHeight(130);
    form->addRow("Joints used", jointList_);

    direction_ = new QComboBox;
    direction_->setObjectName("attackDirection");
    direction_->setEditable(true);
    direction_->addItems({"", "straight", "left", "right", "up", "down"});
    defended_ = new QComboBox;
    defended_->setObjectName("defendedPart");
    defended_->setEditable(true);
    defended_->addItems({"", "head", "torso", "legs"});
    form->addRow("Attack direction", direction_);
    form->addRow("Defended part", defended_);

    hasConditions_ = new QCheckBox("limit (Interaction Patches)");
    hasConditions_->setToolTip("Ranges of the opponent's distance, direction, facing and timing within which this action can succeed");
    hasConditions_->setObjectName("hasInitialConditions");
    auto* grid = new QWidget;
    auto* gridLayout = new QGridLayout(grid);
    gridLayout->setContentsMargins(0, 0, 0, 0);
    const char* rows[] = {"distance", "angle", "facing", "timing"};
    const char* units[] = {" m", " deg", " deg", " s"};
    for (int r = 0; r < 4; ++r) {
        gridLayout->addWidget(new QLabel(rows[r]), r, 0);
        for (int k = 0; k < 2; ++k) {
            auto* spin = new QDoubleSpinBox;
            spin->setObjectName(QString("ic_%1_%2").arg(rows[r], k == 0 ? "min" : "max"));
            spin->setSuffix(units[r]);
            spin->setDecimals(r == 1 || r == 2 ? 0 : 2);
            spin->setSingleStep(r == 1 || r == 2 ? 5.0 : 0.05);
            if (r == 0) spin->setRange(0.0, 10.0);
            else if (r == 3) spin->setRange(-5.0, 5.0);
            else spin->setRange(-180.0, 180.0);
            spin->setKeyboardTracking(false);
            spin->setMinimumWidth(70);
            ic_[r * 2 + k] = spin;
            gridLayout->addWidget(spin, r, 1 + k);
            connect(spin, &QDoubleSpinBox::valueChanged, this, [this] { applyInitialConditions(); });
            connect(spin, &QDoubleSpinBox::editingFinished, this, [this] { icDrag_ = 0; });
        }
    }
    auto* icBox = new QWidget;
    auto* icLayout = new QVBoxLayout(icBox);
    icLayout->setContentsMargins(0, 0, 0, 0);
    icLayout->addWidget(hasConditions_);
    icLayout->addWidget(grid);
    form->addRow("Initial conditions", icBox);

    auto* scroll = new QScrollArea;
    scroll->setWidget(body_);
    scroll->setWidgetResizable(true);
    scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
    scroll->setFrameShape(QFrame::NoFrame);
    outer->addWidget(scroll, 1);

    connect(name_, &QLineEdit::editingFinished, this, [this] {
        if (updating_ || !document_) return;
        report(document_->setActionName(motionId_, action_, ss(name_->text())));
    });
    const auto addWord = [this](const QString& text) {
        if (updating_ || !document_) return;
        const std::string word = ss(text).empty() ? std::string() : ss(text.toLower());
        if (word.empty()) return;
        const prep::ProjectMotion* pm = document_->project().findMotion(motionId_);
        if (!pm || pm->actions.actions[static_cast<std::size_t>(action_)].has(word)) return;
        const auto& vocabulary = document_->project().vocabulary;
        if (std::find(vocabulary.begin(), vocabulary.end(), word) == vocabulary.end()) {
            const Status added = document_->addVocabularyWord(word);
            if (!added) return report(added);
        }
        report(document_->addAnnotation(motionId_, action_, word));
        addAnnotation_->setCurrentText("");
    };
    // Picked from the list, or typed (a new word joins the vocabulary) and Enter.
    connect(addAnnotation_, &QComboBox::textActivated, this, addWord);
    connect(addAnnotation_->lineEdit(), &QLineEdit::returnPressed, this,
            [this, addWord] { addWord(addAnnotation_->lineEdit()->text()); });
    connect(jointList_, &QListWidget::itemChanged, this, [this] {
        if (updating_ || !document_) return;
        std::vector<std::string> joints;
        for (int i = 0; i < jointList_->count(); ++i)
            if (jointList_->item(i)->checkState() == Qt::Checked) joints.push_back(ss(jointList_->item(i)->text()));
        report(document_->setJoints(motionId_, action_, joints));
    });
    const auto wordOrNone = [](const QString& text) -> std::optional<std::string> {
        const std::string s = ss(text);
        if (s.empty()) return std::nullopt;
        return s;
    };
    connect(direction_, &QComboBox::currentTextChanged, this, [this, wordOrNone](const QString& text) {
        if (updating_ || !document_ || direction_->lineEdit()->hasFocus()) return;
        report(document_->setAttackDirection(motionId_, action_, wordOrNone(text)));
    });
    connect(direction_->lineEdit(), &QLineEdit::editingFinished, this, [this, wordOrNone] {
        if (updating_ || !document_) return;
        report(document_->setAttackDirection(motionId_, action_, wordOrNone(direction_->currentText())));
    });
    connect(defended_, &QComboBox::currentTextChanged, this, [this, wordOrNone](const QString& text) {
        if (updating_ || !document_ || defended_->lineEdit()->hasFocus()) return;
        report(document_->setDefendedPart(motionId_, action_, wordOrNone(text)));
    });
    connect(defended_->lineEdit(), &QLineEdit::editingFinished, this, [this, wordOrNone] {
        if (updating_ || !document_) return;
        report(document_->setDefendedPart(motionId_, action_, wordOrNone(defended_->currentText())));
    });
    connect(hasConditions_, &QCheckBox::toggled, this, [this](bool on) {
        if (updating_ || !document_) return;
        for (QDoubleSpinBox* s : ic_) s->setEnabled(on);
        if (!on) {
            report(document_->setInitialConditions(motionId_, action_, std::nullopt));
            return;
        }
        icDrag_ = 0;
        applyInitialConditions();
    });
    clear("Select an action in the library or the timeline.");
}

void InspectorPanel::report(const Status& status) {
    if (!status) Q_EMIT editFailed(QString::fromStdString(status.error().message));
}

void InspectorPanel::applyInitialConditions() {
    if (updating_ || !document_ || !hasConditions_->isChecked()) return;
    prep::InitialConditions c;
    c.minDistance = ic_[0]->value();
    c.maxDistance = ic_[1]->value();
    c.minAngle = ic_[2]->value() / kDegrees;
    c.maxAngle = ic_[3]->value() / kDegrees;
    c.minFacing = ic_[4]->value() / kDegrees;
    c.maxFacing = ic_[5]->value() / kDegrees;
    c.minTiming = ic_[6]->value();
    c.maxTiming = ic_[7]->value();
    // Steps of one spin-box session (arrows held, wheel) merge into one undo step.
    if (icDrag_ == 0) icDrag_ = document_->beginDrag();
    report(document_->setInitialConditions(motionId_, action_, c, icDrag_));
}

void InspectorPanel::clear(const QString& message) {
    document_ = nullptr;
    motionId_.clear();
    action_ = -1;
    title_->setText("Inspector");
    contextLabel_->setText(message);
    body_->setEnabled(false);
    body_->setVisible(false);
}

void InspectorPanel::showAction(authoring::ProjectDocument* document, const std::string& motionId, int action,
                                QStringList joints, QString context) {
    document_ = document;
    motionId_ = motionId;
    action_ = action;
    joints_ = std::move(joints);
    context_ = std::move(context);
    icDrag_ = 0;
    rebuild();
}

void InspectorPanel::refresh() {
    if (document_) rebuild();
}

void InspectorPanel::rebuild() {
    const prep::ProjectMotion* m = document_ ? document_->project().findMotion(motionId_) : nullptr;
    if (!m || action_ < 0 || action_ >= m->actions.actionCount()) {
        clear("Select an action in the library or the timeline.");
        return;
    }
    updating_ = true;
    const prep::ActionInfo& info = m->actions.actions[static_cast<std::size_t>(action_)];
    body_->setEnabled(true);
    body_->setVisible(true);
    title_->setText(info.name.empty() ? QString("%1 #%2").arg(qs(motionId_)).arg(action_) : qs(info.name));
    contextLabel_->setText(context_);
    if (!name_->hasFocus()) name_->setText(qs(info.name));

    // Chips: one button per confirmed annotation; clicking removes it.
    clearLayout(chips_);
    auto* chipsLayout = static_cast<QGridLayout*>(chips_->layout());
    while (chipsLayout->count() > 0) delete chipsLayout->takeAt(0);
    for (const std::string& word : info.annotations) {
        auto* chip = new QToolButton;
        chip->setObjectName(qs("chip:" + word));
        chip->setText(qs(word) + "  x");
        chip->setToolTip("Remove the annotation '" + qs(word) + "'");
        chip->setStyleSheet("QToolButton { background: #9cc3f0; color: #111; border-radius: 8px; padding: 1px 6px; }");
        const std::string w = word;
        connect(chip, &QToolButton::clicked, this, [this, w] { report(document_->removeAnnotation(motionId_, action_, w)); });
        const int n = chipsLayout->count();
        chipsLayout->addWidget(chip, n / 3, n % 3);  // three chips a row
    }
    if (info.annotations.empty()) chipsLayout->addWidget(new QLabel("<i>none</i>"), 0, 0);
    chipsLayout->setColumnStretch(3, 1);
    addAnnotation_->clear();
    for (const std::string& word : document_->project().vocabulary)
        if (std::find(info.annotations.begin(), info.annotations.end(), word) == info.annotations.end())
            addAnnotation_->addItem(qs(word));
    addAnnotation_->setCurrentIndex(-1);
    addAnnotation_->setCurrentText("");

    // Proposals, apart: accept or reject each, or all.
    clearLayout(proposals_);
    auto* proposalsLayout = static_cast<QGridLayout*>(proposals_->layout());
    while (proposalsLayout->count() > 0) delete proposalsLayout->takeAt(0);
    for (const std::string& word : info.proposed) {
        auto* label = new QLabel(qs(word) + "?");
        label->setStyleSheet("QLabel { background: #f0d79c; color: #111; border-radius: 8px; padding: 1px 6px; }");
        auto* accept = new QToolButton;
        accept->setObjectName(qs("accept:" + word));
        accept->setText("Accept");
        auto* reject = new QToolButton;
        reject->setObjectName(qs("reject:" + word));
        reject->setText("Reject");
        const std::string w = word;
        connect(accept, &QToolButton::clicked, this, [this, w] { report(document_->confirmProposal(motionId_, action_, w)); });
        connect(reject, &QToolButton::clicked, this, [this, w] { report(document_->rejectProposal(motionId_, action_, w)); });
        const int row = proposalsLayout->rowCount();  // one proposal a row
        proposalsLayout->addWidget(label, row, 0);
        proposalsLayout->addWidget(accept, row, 1);
        proposalsLayout->addWidget(reject, row, 2);
    }
    if (info.proposed.size() > 1) {
        auto* all = new QPushButton("Accept all");
        all->setObjectName("acceptAll");
        connect(all, &QPushButton::clicked, this, [this] {
            const prep::ProjectMotion* pm = document_->project().findMotion(motionId_);
            if (!pm) return;
            prep::ActionInfo next = pm->actions.actions[static_cast<std::size_t>(action_)];
            for (const std::string& w : next.proposed)
                if (std::find(next.annotations.begin(), next.annotations.end(), w) == next.annotations.end())
                    next.annotations.push_back(w);
            next.proposed.clear();
            report(document_->setActionInfo(motionId_, action_, next));
        });
        auto* none = new QPushButton("Reject all");
        none->setObjectName("rejectAll");
        connect(none, &QPushButton::clicked, this, [this] {
            const prep::ProjectMotion* pm = document_->project().findMotion(motionId_);
            if (!pm) return;
            prep::ActionInfo next = pm->actions.actions[static_cast<std::size_t>(action_)];
            next.proposed.clear();
            report(document_->setActionInfo(motionId_, action_, next));
        });
        const int row = proposalsLayout->rowCount();
        proposalsLayout->addWidget(all, row, 1);
        proposalsLayout->addWidget(none, row, 2);
    }
    if (info.proposed.empty()) proposalsLayout->addWidget(new QLabel("<i>none</i>"), 0, 0);
    proposalsLayout->setColumnStretch(3, 1);

    // Joints used, checked from the skeleton's joint names.
    jointList_->clear();
    for (const QString& joint : joints_) {
        auto* item = new QListWidgetItem(joint, jointList_);
        item->setFlags(item->flags() | Qt::ItemIsUserCheckable);
        const bool used = std::find(info.joints.begin(), info.joints.end(), ss(joint)) != info.joints.end();
        item->setCheckState(used ? Qt::Checked : Qt::Unchecked);
    }
    if (!direction_->lineEdit()->hasFocus()) direction_->setCurrentText(info.attackDirection ? qs(*info.attackDirection) : "");
    if (!defended_->lineEdit()->hasFocus()) defended_->setCurrentText(info.defendedPart ? qs(*info.defendedPart) : "");

    hasConditions_->setChecked(info.initialConditions.has_value());
    const prep::InitialConditions c = info.initialConditions.value_or(prep::InitialConditions{});
    const double values[8] = {c.minDistance,         c.maxDistance,         c.minAngle * kDegrees, c.maxAngle * kDegrees,
                              c.minFacing * kDegrees, c.maxFacing * kDegrees, c.minTiming,           c.maxTiming};
    for (int i = 0; i < 8; ++i) {
        ic_[i]->setEnabled(info.initialConditions.has_value());
        if (!ic_[i]->hasFocus()) ic_[i]->setValue(values[i]);
    }
    updating_ = false;
}

}  // namespace fray::editor
