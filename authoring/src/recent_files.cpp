#include "fray/authoring/recent_files.h"

#include <QDir>
#include <QFileInfo>
#include <QSettings>

#include <algorithm>

namespace fray::authoring {
namespace {

const char* const kFilesKey = "recent_files/files";

}  // namespace

RecentFiles::RecentFiles(QSettings& settings, int capacity, QObject* parent)
    : QObject(parent), settings_(settings), capacity_(std::clamp(capacity, 1, kMaxCapacity)) {}

void RecentFiles::setCapacity(int capacity) {
    capacity_ = std::clamp(capacity, 1, kMaxCapacity);
    const QStringList list = files();
    if (list.size() > capacity_) store(list.mid(0, capacity_));
}

QString RecentFiles::normalized(const QString& file) {
    const QFileInfo info(file);
    const QString canonical = info.canonicalFilePath();  // empty when the file is missing
    return canonical.isEmpty() ? QDir::cleanPath(info.absoluteFilePath()) : canonical;
}

QStringList RecentFiles::files() const {
    // Tolerate a hand-edited settings file: drop empties and repeats.
    QStringList out;
    for (const QString& f : settings_.value(kFilesKey).toStringList()) {
        if (!f.isEmpty() && !out.contains(f) && out.size() < capacity_) out.push_back(f);
    }
    return out;
}

void RecentFiles::store(const QStringList& list) {
    settings_.setValue(kFilesKey, list);
    Q_EMIT changed();
}

void RecentFiles::add(const QString& file) {
    if (file.isEmpty()) return;
    const QString path = normalized(file);
    QStringList list = files();
    list.removeAll(path);
    list.prepend(path);
    while (list.size() > capacity_) list.removeLast();
    store(list);
}

void RecentFiles::remove(const QString& file) {
    QStringList list = files();
    if (list.removeAll(normalized(file)) > 0) store(list);
}

void RecentFiles::clear() { store({}); }

std::vector<RecentFiles::Entry> RecentFiles::entries() const {
    std::vector<Entry> out;
    for (const QString& f : files()) out.push_back({f, QFileInfo(f).isFile()});
    return out;
}

int RecentFiles::prune() {
    QStringList kept;
    for (const QString& f : files()) {
        if (QFileInfo(f).isFile()) kept.push_back(f);
    }
    const int dropped = static_cast<int>(files().size() - kept.size());
    if (dropped > 0) store(kept);
    return dropped;
}

}  // namespace fray::authoring
