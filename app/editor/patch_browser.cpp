#include "patch_browser.h"

#include <QHBoxLayout>
#include <QHeaderView>
#include <QItemSelectionModel>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QSortFilterProxyModel>
#include <QStandardItemModel>
#include <QTableView>
#include <QVBoxLayout>
#include <algorithm>

namespace fray::editor {

namespace {

constexpr int kRolePatch = Qt::UserRole + 30;
enum Column { kIndex, kPattern, kScore, kFirst, kSecond, kDuration, kStatus, kColumns };

}  // namespace

PatchBrowser::PatchBrowser(QWidget* parent) : QWidget(parent) {
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(2, 2, 2, 2);
    auto* bar = new QHBoxLayout;
    filter_ = new QLineEdit;
    filter_->setObjectName("patchFilter");
    filter_->setPlaceholderText("Filter (pattern or action)");
    filter_->setClearButtonEnabled(true);
    keep_ = new QPushButton("Keep");
    keep_->setObjectName("patchKeep");
    keep_->setToolTip("Keep the selected patches (they may be composed)");
    reject_ = new QPushButton("Reject");
    reject_->setObjectName("patchReject");
    reject_->setToolTip("Reject the selected patches: they are never composed");
    bar->addWidget(filter_, 1);
    bar->addWidget(keep_);
    bar->addWidget(reject_);
    auto* handMade = new QPushButton("Hand-made...");
    handMade->setObjectName("patchHandMade");
    handMade->setToolTip("Build a patch action by action: both characters' actions from the library, played by the patch engine, "
                         "added to the library as kept");
    connect(handMade, &QPushButton::clicked, this, &PatchBrowser::handMadeRequested);
    bar->addWidget(handMade);
    layout->addLayout(bar);
    model_ = new QStandardItemModel(0, kColumns, this);
    model_->setHorizontalHeaderLabels({"#", "pattern", "score", "character 1", "character 2", "duration (s)", "status"});
    proxy_ = new QSortFilterProxyModel(this);
    proxy_->setSourceModel(model_);
    proxy_->setFilterKeyColumn(-1);
    proxy_->setFilterCaseSensitivity(Qt::CaseInsensitive);
    proxy_->setSortRole(Qt::DisplayRole);
    table_ = new QTableView;
    table_->setObjectName("patches");
    table_->setModel(proxy_);
    table_->setSortingEnabled(true);
    table_->sortByColumn(kIndex, Qt::AscendingOrder);
    table_->setSelectionBehavior(QAbstractItemView::SelectRows);
    table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
    table_->verticalHeader()->hide();
    table_->horizontalHeader()->setStretchLastSection(true);
    layout->addWidget(table_, 1);
    summary_ = new QLabel("No patches yet: generate them in the PatternList panel.");
    summary_->setObjectName("patchSummary");
    summary_->setWordWrap(true);
    layout->addWidget(summary_);

    connect(filter_, &QLineEdit::textChanged, proxy_, &QSortFilterProxyModel::setFilterFixedString);
    connect(table_->selectionModel(), &QItemSelectionModel::selectionChanged, this, [this] { Q_EMIT patchSelected(selectedPatch()); });
    connect(keep_, &QPushButton::clicked, this, [this] {
        const auto s = selectedPatches();
        if (!s.empty()) Q_EMIT rejectRequested(s, false);
    });
    connect(reject_, &QPushButton::clicked, this, [this] {
        const auto s = selectedPatches();
        if (!s.empty()) Q_EMIT rejectRequested(s, true);
    });
}

QString PatchBrowser::actionsText(const sim::Patch& p, int character, const sim::ActionLibrary& lib) {
    QStringList words;
    for (const sim::ActionInstance& inst : p.tracks[static_cast<std::size_t>(character)]) {
        const auto& a = lib.actions()[static_cast<std::size_t>(inst.action)];
        words << QString::fromStdString(a.label()) + (inst.forced ? "!" : "");
    }
    return words.join(' ');
}

void PatchBrowser::setPatches(std::shared_ptr<const sim::PatchLibrary> patches, const sim::ActionLibrary* lib) {
    patches_ = std::move(patches);
    table_->setSortingEnabled(false);
    model_->removeRows(0, model_->rowCount());
    if (patches_ && lib) {
        for (std::size_t i = 0; i < patches_->patches().size(); ++i) {
            const sim::Patch& p = patches_->patches()[i];
            QList<QStandardItem*> row;
            auto* index = new QStandardItem;
            index->setData(static_cast<int>(i), Qt::DisplayRole);
            index->setData(static_cast<int>(i), kRolePatch);
            row << index;
            row << new QStandardItem(QString::fromStdString(patches_->patterns()[static_cast<std::size_t>(p.pattern)].name));
            auto* score = new QStandardItem;
            score->setData(std::round(p.score * 1000.0) / 1000.0, Qt::DisplayRole);
            row << score;
            row << new QStandardItem(actionsText(p, 0, *lib));
            row << new QStandardItem(actionsText(p, 1, *lib));
            auto* duration = new QStandardItem;
            duration->setData(std::round(p.duration * 100.0) / 100.0, Qt::DisplayRole);
            row << duration;
            row << new QStandardItem("kept");
            model_->appendRow(row);
        }
    }
    table_->setSortingEnabled(true);
    table_->resizeColumnsToContents();
    fillStatus();
}

void PatchBrowser::setRejected(const std::vector<int>& rejected) {
    rejected_ = rejected;
    fillStatus();
}

void PatchBrowser::fillStatus() {
    int rejectedCount = 0;
    for (int r = 0; r < model_->rowCount(); ++r) {
        const int patch = model_->item(r, kIndex)->data(kRolePatch).toInt();
        const bool rejected = std::find(rejected_.begin(), rejected_.end(), patch) != rejected_.end();
        rejectedCount += rejected ? 1 : 0;
        QStandardItem* status = model_->item(r, kStatus);
        status->setText(rejected ? "rejected" : "kept");
        status->setForeground(rejected ? QBrush(QColor(200, 40, 40)) : QBrush());
    }
    if (!patches_) return;
    summary_->setText(QString("%1 patches from %2 PatternLists, %3 rejected. Select one to play it; Reject keeps it out of "
                              "every composed scene.")
                          .arg(patches_->patches().size())
                          .arg(patches_->patterns().size())
                          .arg(rejectedCount));
}

int PatchBrowser::patchAtRow(int row) const {
    const QModelIndex i = proxy_->index(row, kIndex);
    return i.isValid() ? proxy_->mapToSource(i).data(kRolePatch).toInt() : -1;
}

int PatchBrowser::rowOfPatch(int patch) const {
    for (int r = 0; r < proxy_->rowCount(); ++r)
        if (patchAtRow(r) == patch) return r;
    return -1;
}

int PatchBrowser::selectedPatch() const {
    const auto rows = table_->selectionModel()->selectedRows();
    return rows.size() == 1 ? patchAtRow(rows.front().row()) : -1;
}

void PatchBrowser::selectPatch(int patch) {
    const int row = rowOfPatch(patch);
    if (row < 0) return table_->clearSelection();
    table_->selectRow(row);
    table_->scrollTo(proxy_->index(row, 0));
}

std::vector<int> PatchBrowser::selectedPatches() const {
    std::vector<int> out;
    for (const QModelIndex& i : table_->selectionModel()->selectedRows()) out.push_back(patchAtRow(i.row()));
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace fray::editor
