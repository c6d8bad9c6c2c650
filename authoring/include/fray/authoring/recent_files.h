#pragma once
// The recent-files list (File > Open Recent), kept in QSettings under
// "recent_files": absolute paths, most recent first, no repeats, at most
// capacity() entries (default 10, up to 30 like Blender). Missing files are
// flagged by entries() and dropped by prune().
#include <QObject>
#include <QString>
#include <QStringList>

#include <vector>

class QSettings;

namespace fray::authoring {

class RecentFiles : public QObject {
    Q_OBJECT

public:
    static constexpr int kDefaultCapacity = 10;
    static constexpr int kMaxCapacity = 30;

    // The settings object must outlive this list.
    explicit RecentFiles(QSettings& settings, int capacity = kDefaultCapacity, QObject* parent = nullptr);

    int capacity() const { return capacity_; }
    // Clamped to 1..kMaxCapacity; a smaller capacity trims the stored list.
    void setCapacity(int capacity);

    // Moves (or adds) the file to the front.
    void add(const QString& file);
    void remove(const QString& file);
    void clear();

    QStringList files() const;
    struct Entry {
        QString path;
        bool exists = false;
    };
    std::vector<Entry> entries() const;
    // Drops the files that no longer exist; returns how many.
    int prune();

    // The form stored and compared: absolute, cleaned, symlinks resolved when the file exists.
    static QString normalized(const QString& file);

Q_SIGNALS:
    void changed();

private:
    void store(const QStringList& files);
    QSettings& settings_;
    int capacity_;
};

}  // namespace fray::authoring
