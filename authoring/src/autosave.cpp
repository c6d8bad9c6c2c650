#include "fray/authoring/autosave.h"

#include <QCoreApplication>
#include <QSettings>

#include <algorithm>

#include "fray/core/atomic_file.h"

namespace fray::authoring {
namespace {

namespace fs = std::filesystem;
const char* const kIntervalKey = "autosave/interval_seconds";

}  // namespace

fs::path autosavePath(const fs::path& projectFile) {
    fs::path p = projectFile;
    p += ".autosave";
    return p;
}

Autosaver::Autosaver(ProjectDocument* document, QObject* parent)
    : QObject(parent), document_(document) {
    // A document that is already dirty (recovered, or edited before the
    // autosaver came) is written at the first chance.
    if (!document_->isDirty()) writtenRevision_ = document_->revision();
    connect(&timer_, &QTimer::timeout, this, [this] { (void)autosaveNow(); });
    // A saved document is on disk: the autosave is stale from then on.
    connect(document_, &ProjectDocument::saved, this, [this] {
        writtenRevision_ = document_->revision();
        removeAutosave();
    });
    // After a Save As the autosave beside the old file is stale too.
    connect(document_, &ProjectDocument::fileChanged, this, [this] {
        if (written_.empty()) return;
        std::error_code ec;
        fs::remove(written_, ec);
        written_.clear();
    });
    setIntervalSeconds(kDefaultIntervalSeconds);
}

void Autosaver::setIntervalSeconds(int seconds) {
    intervalSeconds_ = std::max(0, seconds);
    // Timers need an event loop; a headless tool without one calls autosaveNow itself.
    if (intervalSeconds_ == 0 || !QCoreApplication::instance()) {
        timer_.stop();
    } else {
        timer_.start(std::chrono::seconds(intervalSeconds_));
    }
}

int Autosaver::intervalFromSettings(const QSettings& settings) {
    bool ok = false;
    const int s = settings.value(kIntervalKey, kDefaultIntervalSeconds).toInt(&ok);
    return ok && s >= 0 ? s : kDefaultIntervalSeconds;
}

void Autosaver::storeInterval(QSettings& settings, int seconds) { settings.setValue(kIntervalKey, std::max(0, seconds)); }

Status Autosaver::autosaveNow() {
    const fs::path& file = document_->filePath();
    if (file.empty()) return {};
    if (!document_->isDirty()) {
        // Back at the saved state (e.g. undone to it): the file on disk is the document.
        writtenRevision_ = document_->revision();
        removeAutosave();
        return {};
    }
    if (document_->revision() == writtenRevision_) return {};
    const fs::path target = autosavePath(file);
    if (auto st = writeFileAtomically(target, document_->serialized()); !st) {
        Q_EMIT failed(QStringLiteral("autosave: %1").arg(QString::fromStdString(st.error().message)));
        return st;
    }
    writtenRevision_ = document_->revision();
    written_ = target;
    Q_EMIT autosaved(QString::fromStdString(target.string()));
    return {};
}

void Autosaver::removeAutosave() {
    if (document_->filePath().empty()) return;
    std::error_code ec;
    fs::remove(autosavePath(document_->filePath()), ec);
}

std::optional<Recovery> findRecovery(const fs::path& projectFile) {
    std::error_code ec;
    const fs::path autosave = autosavePath(projectFile);
    if (!fs::is_regular_file(autosave, ec)) return std::nullopt;
    const auto autosaveTime = fs::last_write_time(autosave, ec);
    if (ec) return std::nullopt;
    const auto projectTime = fs::last_write_time(projectFile, ec);
    if (!ec && projectTime >= autosaveTime) return std::nullopt;  // saved after the autosave
    return Recovery{projectFile, autosave, autosaveTime};
}

Result<std::unique_ptr<ProjectDocument>> recoverDocument(const Recovery& recovery) {
    auto text = readWholeFile(recovery.autosaveFile, "the autosave");
    if (!text) return text.error();
    auto project = prep::projectFromJson(*text, recovery.autosaveFile.string());
    if (!project) return project.error();
    auto doc = std::make_unique<ProjectDocument>(std::move(*project), recovery.projectFile);
    doc->rememberDiskState();
    doc->markDirty();
    return doc;
}

Status discardRecovery(const Recovery& recovery) {
    std::error_code ec;
    fs::remove(recovery.autosaveFile, ec);
    if (ec) return makeError(recovery.autosaveFile.string() + ": cannot remove the autosave: " + ec.message());
    return {};
}

}  // namespace fray::authoring
