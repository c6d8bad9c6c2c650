#include "patterns_panel.h"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QInputDialog>
#include <QLabel>
#include <QLineEdit>
#include <QListWidget>
#include <QPushButton>
#include <QSignalBlocker>
#include <QTableWidget>
#include <QTimer>
#include <QVBoxLayout>
#include <algorithm>

namespace fray::editor {

namespace {

constexpr int kRoleEntry = Qt::UserRole + 20;

QString qs(const std::string& s) { return QString::fromStdString(s); }

QDoubleSpinBox* spin(const char* name, double lo, double hi, double step, int decimals, const QString& tip) {
    auto* s = new QDoubleSpinBox;
    s->setObjectName(name);
    s->setRange(lo, hi);
    s->setSingleStep(step);
    s->setDecimals(decimals);
    s->setKeyboardTracking(false);
    s->setToolTip(tip);
    return s;
}

}  // namespace

QString patternRowText(const sim::PatternEntry& e) { return QString("%1: %2").arg(e.character + 1).arg(qs(e.annotation)); }

PatternsPanel::PatternsPanel(QWidget* parent) : QWidget(parent) {
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(2, 2, 2, 2);

    auto* top = new QHBoxLayout;
    lists_ = new QComboBox;
    lists_->setObjectName("patternLists");
    lists_->setToolTip("The project's PatternLists");
    addList_ = new QPushButton("New...");
    addList_->setToolTip("A new PatternList: character 1 plays the annotation of the row controls below, character 2 "
                         "answers with any action; edit the rows from there");
    addList_->setObjectName("patternNew");
    removeList_ = new QPushButton("Delete");
    removeList_->setObjectName("patternDelete");
    top->addWidget(lists_, 1);
    top->addWidget(addList_);
    top->addWidget(removeList_);
    layout->addLayout(top);

    rows_ = new QListWidget;
    rows_->setObjectName("patternRows");
    rows_->setToolTip("The rows in order: which character (1 or 2) plays an action of which annotation. Drag to reorder.");
    rows_->setDragDropMode(QAbstractItemView::InternalMove);
    rows_->setDefaultDropAction(Qt::MoveAction);
    rows_->setSelectionMode(QAbstractItemView::SingleSelection);
    rows_->setMinimumHeight(90);
    layout->addWidget(rows_, 1);

    auto* rowBar = new QHBoxLayout;
    rowCharacter_ = new QComboBox;
    rowCharacter_->setObjectName("patternRowCharacter");
    rowCharacter_->addItems({"character 1", "character 2"});
    rowAnnotation_ = new QComboBox;
    rowAnnotation_->setObjectName("patternRowAnnotation");
    rowAnnotation_->setEditable(true);
    rowAnnotation_->setInsertPolicy(QComboBox::NoInsert);
    rowAnnotation_->setToolTip("A vocabulary word, or a group: attack (punch or kick), defence (avoid or dodge), fall, any");
    addRow_ = new QPushButton("Add row");
    addRow_->setObjectName("patternAddRow");
    removeRow_ = new QPushButton("Remove row");
    removeRow_->setObjectName("patternRemoveRow");
    rowBar->addWidget(rowCharacter_);
    rowBar->addWidget(rowAnnotation_, 1);
    rowBar->addWidget(addRow_);
    rowBar->addWidget(removeRow_);
    layout->addLayout(rowBar);

    auto* form = new QFormLayout;
    auto* weights = new QHBoxLayout;
    wContact_ = spin("patternWContact", 0, 100, 0.1, 2, "Weight of the contact criterion (SPEC 4.2)");
    wDistance_ = spin("patternWDistance", 0, 100, 0.1, 2, "Weight of the distance criterion");
    wTiming_ = spin("patternWTiming", 0, 100, 0.1, 2, "Weight of the timing criterion");
    weights->addWidget(new QLabel("contact"));
    weights->addWidget(wContact_);
    weights->addWidget(new QLabel("distance"));
    weights->addWidget(wDistance_);
    weights->addWidget(new QLabel("timing"));
    weights->addWidget(wTiming_);
    form->addRow("Weights", weights);
    auto* thresholds = new QHBoxLayout;
    threshold_ = spin("patternThreshold", 0, 1, 0.05, 2, "Score a path needs to become a patch (0-1)");
    thresholds->addWidget(threshold_);
    thresholds->addStretch(1);
    form->addRow("Threshold", thresholds);
    layout->addLayout(form);

    ranges_ = new QTableWidget(0, 7);
    ranges_->setObjectName("patternRanges");
    ranges_->setHorizontalHeaderLabels({"annotation", "min r (m)", "max r (m)", "min angle", "max angle", "min delay", "max delay"});
    ranges_->verticalHeader()->hide();
    ranges_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
    ranges_->setToolTip("Valid initial conditions per annotation (SPEC 4.1): distance, angle to the other (deg), delay (s). "
                        "Double-click a value to change it.");
    ranges_->setMaximumHeight(130);
    layout->addWidget(ranges_);

    auto* genBar = new QHBoxLayout;
    generate_ = new QPushButton("Generate patches");
    generate_->setObjectName("patternGenerate");
    generate_->setToolTip("Generate the Interaction Patches of this PatternList in the background");
    generateAll_ = new QPushButton("Generate all");
    generateAll_->setObjectName("patternGenerateAll");
    generateAll_->setToolTip("Generate the patches of every PatternList (the default ones the actions can play when the "
                             "project has none)");
    genBar->addWidget(generate_);
    genBar->addWidget(generateAll_);
    genBar->addStretch(1);
    layout->addLayout(genBar);
    report_ = new QLabel;
    report_->setObjectName("patternReport");
    report_->setWordWrap(true);
    report_->setTextInteractionFlags(Qt::TextSelectableByMouse);
    layout->addWidget(report_);

    connect(lists_, &QComboBox::currentIndexChanged, this, [this](int i) {
        if (filling_) return;
        current_ = i;
        fillRows();
        fillRanges();
    });
    connect(addList_, &QPushButton::clicked, this, [this] {
        bool ok = false;
        const QString name = QInputDialog::getText(this, "New PatternList", "Name", QLineEdit::Normal, "pattern", &ok).trimmed();
        const QString word = rowAnnotation_->currentText().trimmed();
        if (ok && !name.isEmpty() && !word.isEmpty())
            Q_EMIT patternAddRequested(name, sim::PatternEntry{0, word.toStdString()});
    });
    connect(removeList_, &QPushButton::clicked, this, [this] {
        if (currentList()) Q_EMIT patternRemoveRequested(currentName());
    });
    connect(addRow_, &QPushButton::clicked, this, [this] {
        const sim::PatternList* p = currentList();
        const QString word = rowAnnotation_->currentText().trimmed();
        if (!p || word.isEmpty()) return;
        // After the selected row, else at the end.
        const int at = rows_->currentRow() >= 0 ? rows_->currentRow() + 1 : static_cast<int>(p->entries.size());
        Q_EMIT rowAddRequested(currentName(), at, sim::PatternEntry{rowCharacter_->currentIndex(), word.toStdString()});
    });
    connect(removeRow_, &QPushButton::clicked, this, [this] {
        const sim::PatternList* p = currentList();
        const int r = rows_->currentRow();
        if (p && r >= 0 && r < static_cast<int>(p->entries.size())) Q_EMIT rowRemoveRequested(currentName(), r);
    });
    // A drop moves one row: report it, and show the set as it is until the
    // document's change event brings the new order.
    connect(rows_->model(), &QAbstractItemModel::rowsMoved, this,
            [this](const QModelIndex&, int start, int, const QModelIndex&, int row) {
                if (filling_) return;
                const int to = row > start ? row - 1 : row;
                const QString name = currentName();
                QTimer::singleShot(0, this, [this, name, start, to] {
                    fillRows();
                    if (start != to) Q_EMIT rowMoveRequested(name, start, to);
                });
            });
    const auto weightEdit = [this](auto member) {
        return [this, member](double v) {
            const sim::PatternList* p = currentList();
            if (filling_ || !p) return;
            sim::PatternWeights w = p->weights;
            w.*member = v;
            Q_EMIT weightsRequested(currentName(), w);
        };
    };
    connect(wContact_, &QDoubleSpinBox::valueChanged, this, weightEdit(&sim::PatternWeights::contact));
    connect(wDistance_, &QDoubleSpinBox::valueChanged, this, weightEdit(&sim::PatternWeights::distance));
    connect(wTiming_, &QDoubleSpinBox::valueChanged, this, weightEdit(&sim::PatternWeights::timing));
    connect(threshold_, &QDoubleSpinBox::valueChanged, this, [this](double v) {
        if (!filling_ && currentList()) Q_EMIT thresholdRequested(currentName(), v);
    });
    connect(ranges_, &QTableWidget::cellChanged, this, &PatternsPanel::rangeEdited);
    connect(generate_, &QPushButton::clicked, this, [this] {
        if (current_ >= 0 && current_ < static_cast<int>(set_.patterns.size()))
            Q_EMIT generateRequested({qs(set_.patterns[static_cast<std::size_t>(current_)].name)});
    });
    connect(generateAll_, &QPushButton::clicked, this, [this] { Q_EMIT generateRequested({}); });
    fill();
}

const sim::PatternList* PatternsPanel::currentList() const {
    if (current_ < 0 || current_ >= static_cast<int>(set_.patterns.size())) return nullptr;
    return &set_.patterns[static_cast<std::size_t>(current_)];
}

QString PatternsPanel::currentName() const {
    const sim::PatternList* p = currentList();
    return p ? qs(p->name) : QString();
}

void PatternsPanel::setPatterns(const sim::PatternSet& set, const QStringList& words) {
    set_ = set;
    words_ = words;
    if (current_ >= static_cast<int>(set_.patterns.size())) current_ = static_cast<int>(set_.patterns.size()) - 1;
    if (current_ < 0 && !set_.patterns.empty()) current_ = 0;
    fill();
}

void PatternsPanel::setCurrent(int index) {
    current_ = index;
    fill();
}

void PatternsPanel::setReport(const QString& text) { report_->setText(text); }

void PatternsPanel::setGenerating(bool running) {
    generate_->setEnabled(!running && current_ >= 0);
    generateAll_->setEnabled(!running);
}

void PatternsPanel::fill() {
    filling_ = true;
    {
        const QSignalBlocker quiet(lists_);
        lists_->clear();
        for (const sim::PatternList& p : set_.patterns) lists_->addItem(qs(p.name));
        lists_->setCurrentIndex(current_);
        const QString typed = rowAnnotation_->currentText();
        rowAnnotation_->clear();
        rowAnnotation_->addItems(words_);
        rowAnnotation_->setCurrentText(typed.isEmpty() && !words_.isEmpty() ? words_.front() : typed);
    }
    filling_ = false;
    fillRows();
    fillRanges();
}

void PatternsPanel::fillRows() {
    filling_ = true;
    rows_->clear();
    const sim::PatternList* p = current_ >= 0 && current_ < static_cast<int>(set_.patterns.size())
                                    ? &set_.patterns[static_cast<std::size_t>(current_)]
                                    : nullptr;
    const bool has = p != nullptr;
    for (QWidget* w : std::initializer_list<QWidget*>{rows_, addRow_, removeRow_, wContact_, wDistance_, wTiming_, threshold_,
                                                      ranges_, removeList_, generate_})
        w->setEnabled(has);
    if (p) {
        for (std::size_t e = 0; e < p->entries.size(); ++e) {
            auto* item = new QListWidgetItem(patternRowText(p->entries[e]));
            item->setData(kRoleEntry, static_cast<int>(e));
            item->setFlags(Qt::ItemIsSelectable | Qt::ItemIsEnabled | Qt::ItemIsDragEnabled);
            rows_->addItem(item);
        }
        wContact_->setValue(p->weights.contact);
        wDistance_->setValue(p->weights.distance);
        wTiming_->setValue(p->weights.timing);
        threshold_->setValue(p->threshold);
    }
    filling_ = false;
}

void PatternsPanel::fillRanges() {
    filling_ = true;
    ranges_->setRowCount(0);
    if (current_ >= 0 && current_ < static_cast<int>(set_.patterns.size())) {
        std::vector<std::string> words;
        for (const sim::PatternEntry& e : set_.patterns[static_cast<std::size_t>(current_)].entries)
            if (std::find(words.begin(), words.end(), e.annotation) == words.end()) words.push_back(e.annotation);
        for (const std::string& w : words) {
            const sim::InitialRange r = set_.rangeFor(w);
            const int row = ranges_->rowCount();
            ranges_->insertRow(row);
            auto* name = new QTableWidgetItem(qs(w));
            name->setFlags(Qt::ItemIsEnabled);
            ranges_->setItem(row, 0, name);
            const double values[] = {r.minDistance, r.maxDistance, r.minAngle, r.maxAngle, r.minDelay, r.maxDelay};
            for (int k = 0; k < 6; ++k) {
                auto* item = new QTableWidgetItem;
                item->setData(Qt::DisplayRole, values[k]);
                ranges_->setItem(row, k + 1, item);
            }
        }
    }
    filling_ = false;
}

void PatternsPanel::rangeEdited(int row, int column) {
    if (filling_ || column < 1) return;
    const std::string word = ranges_->item(row, 0)->text().toStdString();
    sim::InitialRange r = set_.rangeFor(word);
    const double v = ranges_->item(row, column)->data(Qt::DisplayRole).toDouble();
    double* fields[] = {&r.minDistance, &r.maxDistance, &r.minAngle, &r.maxAngle, &r.minDelay, &r.maxDelay};
    *fields[column - 1] = v;
    Q_EMIT rangeRequested(qs(word), r);
}

}  // namespace fray::editor
