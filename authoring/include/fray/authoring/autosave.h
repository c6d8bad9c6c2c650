#pragma once
// Autosave and crash recovery (issue 22, EDITOR.md): a timer writes the
// document beside its project file (P.frayproj -> P.frayproj.autosave),
// atomically, only when it changed since the last autosave. The project file
// itself is never touched by autosave. A clean Save removes the autosave;
// one left behind (a crash) that is newer than its project is offered back on
// the next open through findRecovery / recoverDocument.
#include <QObject>
#include <QString>
#include <QTimer>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>

#include "fray/authoring/project_document.h"
#include "fray/core/result.h"

class QSettings;

namespace fray::authoring {

std::filesystem::path autosavePath(const std::filesystem::path& projectFile);

class Autosaver : public QObject {
    Q_OBJECT

public:
    static constexpr int kDefaultIntervalSeconds = 120;

    // Starts the timer at the default interval (when a QCoreApplication exists:
    // timers need its event loop). The document must outlive it.
    explicit Autosaver(ProjectDocument* document, QObject* parent = nullptr);

    // 0 turns autosave off. Negative values are clamped to 0.
    void setIntervalSeconds(int seconds);
    int intervalSeconds() const { return intervalSeconds_; }
    // The "autosave/interval_seconds" setting (default 2 minutes).
    static int intervalFromSettings(const QSettings& settings);
    static void storeInterval(QSettings& settings, int seconds);

    // Writes now when the document changed since the last autosave (or since
    // it was opened or saved). Untitled documents are skipped (nowhere to put
    // the file beside). Returns the error it also signals through failed().
    Status autosaveNow();
    // Deletes the autosave file (after a clean save, or when the user closes
    // the project discarding changes).
    void removeAutosave();

Q_SIGNALS:
    void autosaved(const QString& file);
    void failed(const QString& message);

private:
    ProjectDocument* document_;
    QTimer timer_;
    int intervalSeconds_ = kDefaultIntervalSeconds;
    std::optional<std::uint64_t> writtenRevision_;  // the revision on disk, if known
    std::filesystem::path written_;  // the last autosave written
};

// An autosave newer than its project (or whose project is gone).
struct Recovery {
    std::filesystem::path projectFile;
    std::filesystem::path autosaveFile;
    std::filesystem::file_time_type autosaveTime;
};
std::optional<Recovery> findRecovery(const std::filesystem::path& projectFile);
// The document exactly as it was at the last autosave, titled with the
// project file and dirty (its contents are not on disk there). The autosave
// stays until the document is saved or the recovery discarded. Errors name
// the autosave file and the bad field.
Result<std::unique_ptr<ProjectDocument>> recoverDocument(const Recovery& recovery);
// The user declined: remove the autosave.
Status discardRecovery(const Recovery& recovery);

}  // namespace fray::authoring
