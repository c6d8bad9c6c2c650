#pragma once
// The inspector: the selected action's description, edited through the
// document (every change is one undo command). Annotations are chips from the
// project's vocabulary (an unknown word typed in is added to the vocabulary
// first, as its own undo step); proposals sit apart and are accepted or
// rejected one by one or all at once; joints used are checked from the
// skeleton; attack direction and defended part are free words with
// suggestions; the initial-condition ranges carry their units (m, degrees, s).
#include <QString>
#include <QStringList>
#include <QWidget>
#include <string>

#include "fray/core/result.h"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QLineEdit;
class QListWidget;
class QVBoxLayout;

namespace fray::authoring {
class ProjectDocument;
}

namespace fray::editor {

class InspectorPanel : public QWidget {
    Q_OBJECT
public:
    explicit InspectorPanel(QWidget* parent = nullptr);

    // Shows (motionId, action) of the document; an empty id or null document
    // clears the panel. `joints` are the skeleton's joint names; `context` a
    // line of read-only facts (frames, graph node).
    void showAction(authoring::ProjectDocument* document, const std::string& motionId, int action, QStringList joints,
                    QString context);
    void clear(const QString& message);
    // Re-reads the action from the document (after an undo, say).
    void refresh();
    const std::string& motionId() const { return motionId_; }
    int action() const { return action_; }

Q_SIGNALS:
    // An edit was refused by the document: the message names why.
    void editFailed(const QString& message);

private:
    void rebuild();
    void report(const Status& status);
    void applyInitialConditions();

    authoring::ProjectDocument* document_ = nullptr;
    std::string motionId_;
    int action_ = -1;
    QStringList joints_;
    QString context_;
    bool updating_ = false;
    int icDrag_ = 0;

    QLabel* title_;
    QLabel* contextLabel_;
    QLineEdit* name_;
    QWidget* chips_;
    QComboBox* addAnnotation_;
    QWidget* proposals_;
    QListWidget* jointList_;
    QComboBox* direction_;
    QComboBox* defended_;
    QCheckBox* hasConditions_;
    QDoubleSpinBox* ic_[8];
    QWidget* body_;
};

}  // namespace fray::editor
