#pragma once
// The patch browser (SPEC 4.2-4.4): the Interaction Patches generated from the
// PatternLists in a sortable table (pattern, score, both characters' actions,
// duration, kept or rejected); selecting one asks the window to play it
// looping in the viewport; Keep and Reject mark the selected patches (a
// rejected patch is never composed).
#include <QWidget>
#include <memory>
#include <vector>

#include "fray/sim/action_library.h"
#include "fray/sim/patches.h"

class QLabel;
class QLineEdit;
class QPushButton;
class QSortFilterProxyModel;
class QStandardItemModel;
class QTableView;

namespace fray::editor {

class PatchBrowser : public QWidget {
    Q_OBJECT
public:
    explicit PatchBrowser(QWidget* parent = nullptr);

    // The patches shown (null: none yet) and the action names they use.
    void setPatches(std::shared_ptr<const sim::PatchLibrary> patches, const sim::ActionLibrary* lib);
    // Which patches are rejected (indices into the library).
    void setRejected(const std::vector<int>& rejected);
    const std::vector<int>& rejected() const { return rejected_; }
    // The patch of a table row as shown now (sorted, filtered), and back.
    int patchAtRow(int row) const;
    int rowOfPatch(int patch) const;
    int selectedPatch() const;
    void selectPatch(int patch);
    QTableView* table() const { return table_; }

    // The actions of a patch's character (0 or 1) as text: "jab cross! ..." ('!' a forced reaction).
    static QString actionsText(const sim::Patch& p, int character, const sim::ActionLibrary& lib);

Q_SIGNALS:
    void patchSelected(int patch);  // -1: none
    // Keep (false) or reject (true) these patches.
    void rejectRequested(const std::vector<int>& patches, bool reject);
    // "Hand-made...": build a patch action by action.
    void handMadeRequested();

private:
    std::vector<int> selectedPatches() const;
    void fillStatus();

    std::shared_ptr<const sim::PatchLibrary> patches_;
    std::vector<int> rejected_;
    QStandardItemModel* model_ = nullptr;
    QSortFilterProxyModel* proxy_ = nullptr;
    QTableView* table_ = nullptr;
    QLineEdit* filter_ = nullptr;
    QPushButton* keep_ = nullptr;
    QPushButton* reject_ = nullptr;
    QLabel* summary_ = nullptr;
};

}  // namespace fray::editor
