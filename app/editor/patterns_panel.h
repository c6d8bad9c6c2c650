#pragma once
// The PatternList editor (SPEC 4.1, thesis 6.3.2): the project's PatternLists,
// each an ordered list of (character 1|2, annotation) rows you add, remove and
// drag to reorder; its evaluation weights, threshold and near-duplicate
// setting; the initial-condition ranges of the annotations it uses; and
// "Generate patches" with the reasons paths were discarded.
//
// Like the other panels it holds no authoritative state: it shows a
// PatternSet snapshot and reports every edit as a request (add a row, move
// one...); the window turns each into one undo command on the document,
// whose change event brings the new set back.
#include <QString>
#include <QStringList>
#include <QWidget>

#include "fray/sim/patterns.h"

class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QListWidget;
class QPushButton;
class QTableWidget;

namespace fray::editor {

class PatternsPanel : public QWidget {
    Q_OBJECT
public:
    explicit PatternsPanel(QWidget* parent = nullptr);

    // The set shown and the annotation words offered (the project's vocabulary and the groups).
    void setPatterns(const sim::PatternSet& set, const QStringList& words);
    const sim::PatternSet& patterns() const { return set_; }
    // The PatternList shown (-1: none).
    int current() const { return current_; }
    void setCurrent(int index);
    // What the last patch generation said (per PatternList: kept and discarded paths).
    void setReport(const QString& text);
    // Whether a generation is running (the button is disabled meanwhile).
    void setGenerating(bool running);

Q_SIGNALS:
    // A new PatternList starting with `firstRow` for character 1 and "any" for
    // character 2 (a PatternList needs rows for both).
    void patternAddRequested(const QString& name, const fray::sim::PatternEntry& firstRow);
    void patternRemoveRequested(const QString& name);
    void rowAddRequested(const QString& pattern, int index, const fray::sim::PatternEntry& row);
    void rowRemoveRequested(const QString& pattern, int index);
    void rowMoveRequested(const QString& pattern, int from, int to);
    void weightsRequested(const QString& pattern, const fray::sim::PatternWeights& weights);
    void thresholdRequested(const QString& pattern, double threshold);
    void rangeRequested(const QString& annotation, const fray::sim::InitialRange& range);
    // Generate patches for these PatternLists (empty: all).
    void generateRequested(const QStringList& names);

private:
    void fill();
    void fillRows();
    void fillRanges();
    const sim::PatternList* currentList() const;
    QString currentName() const;
    void rangeEdited(int row, int column);

    sim::PatternSet set_;
    QStringList words_;
    int current_ = -1;
    bool filling_ = false;

    QComboBox* lists_ = nullptr;
    QPushButton* addList_ = nullptr;
    QPushButton* removeList_ = nullptr;
    QListWidget* rows_ = nullptr;
    QComboBox* rowCharacter_ = nullptr;
    QComboBox* rowAnnotation_ = nullptr;
    QPushButton* addRow_ = nullptr;
    QPushButton* removeRow_ = nullptr;
    QDoubleSpinBox* wContact_ = nullptr;
    QDoubleSpinBox* wDistance_ = nullptr;
    QDoubleSpinBox* wTiming_ = nullptr;
    QDoubleSpinBox* threshold_ = nullptr;
    QTableWidget* ranges_ = nullptr;
    QPushButton* generate_ = nullptr;
    QPushButton* generateAll_ = nullptr;
    QLabel* report_ = nullptr;
};

// "1: punch" (character 1-based).
QString patternRowText(const sim::PatternEntry& e);

}  // namespace fray::editor
