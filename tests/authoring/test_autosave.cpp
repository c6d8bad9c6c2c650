// Autosave beside the project, crash recovery restoring the exact document,
// and the recent-files list.
#include <gtest/gtest.h>

#include <QCoreApplication>
#include <QEventLoop>
#include <QSettings>
#include <QTimer>

#include "document_fixture.h"
#include "fray/authoring/autosave.h"
#include "fray/authoring/recent_files.h"

using namespace fray;
using namespace fray::authoring;
namespace fs = std::filesystem;

namespace {

const std::string kBox = "shadowbox_energetic";

// Makes `file` look written `seconds` after `reference`.
void touchAfter(const fs::path& file, const fs::path& reference, int seconds) {
    fs::last_write_time(file, fs::last_write_time(reference) + std::chrono::seconds(seconds));
}

}  // namespace

TEST(Autosave, WritesBesideTheProjectAndRecoveryRestoresTheExactDocument) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    const fs::path file = doc->filePath();
    const std::string onDisk = test::readFile(file);
    Autosaver autosaver(doc.get());
    EXPECT_EQ(autosaver.intervalSeconds(), 120);

    // Nothing to write for an unchanged document.
    ASSERT_TRUE(autosaver.autosaveNow().ok());
    EXPECT_FALSE(fs::exists(autosavePath(file)));

    ASSERT_TRUE(doc->setActionName(kBox, 2, "lead_hook").ok());
    ASSERT_TRUE(doc->addCut(kBox, doc->project().findMotion(kBox)->actions.firstFrame(6) + 4).ok());
    ASSERT_TRUE(doc->renameVocabularyWord("punch", "strike").ok());
    ASSERT_TRUE(autosaver.autosaveNow().ok());
    EXPECT_EQ(autosavePath(file), fs::path(file.string() + ".autosave"));
    const std::string autosaved = doc->serialized();
    EXPECT_EQ(test::readFile(autosavePath(file)), autosaved);
    EXPECT_EQ(test::readFile(file), onDisk) << "autosave must never touch the project file";

    // Edits after the last autosave are lost in the crash.
    ASSERT_TRUE(doc->setGraphThreshold(4.0).ok());
    doc.reset();  // the crash: no save
    touchAfter(autosavePath(file), file, 5);

    const auto recovery = findRecovery(file);
    ASSERT_TRUE(recovery.has_value());
    EXPECT_EQ(recovery->autosaveFile, autosavePath(file));
    auto recovered = recoverDocument(*recovery);
    ASSERT_TRUE(recovered.ok()) << recovered.error().message;
    ProjectDocument& r = **recovered;
    EXPECT_EQ(r.serialized(), autosaved);
    EXPECT_EQ(r.filePath(), file);
    EXPECT_TRUE(r.isDirty()) << "the recovered contents are not on disk yet";
    EXPECT_TRUE(fs::exists(autosavePath(file))) << "kept until saved or discarded";

    // Saving the recovered document writes it and retires the autosave.
    Autosaver again(&r);
    ASSERT_TRUE(r.save().ok());
    EXPECT_EQ(test::readFile(file), autosaved);
    EXPECT_FALSE(fs::exists(autosavePath(file)));
    EXPECT_FALSE(findRecovery(file).has_value());
}

TEST(Autosave, OnlyAnAutosaveNewerThanItsProjectIsOffered) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    const fs::path file = doc->filePath();
    Autosaver autosaver(doc.get());
    ASSERT_TRUE(doc->setName("changed").ok());
    ASSERT_TRUE(autosaver.autosaveNow().ok());
    ASSERT_TRUE(fs::exists(autosavePath(file)));

    touchAfter(file, autosavePath(file), 5);  // the project was saved later (another session)
    EXPECT_FALSE(findRecovery(file).has_value());
    touchAfter(autosavePath(file), file, 5);
    const auto recovery = findRecovery(file);
    ASSERT_TRUE(recovery.has_value());
    ASSERT_TRUE(discardRecovery(*recovery).ok());
    EXPECT_FALSE(fs::exists(autosavePath(file)));
    EXPECT_FALSE(findRecovery(file).has_value());

    // Undoing back to the saved state makes the autosave pointless: it goes.
    ASSERT_TRUE(doc->setName("changed again").ok());
    ASSERT_TRUE(autosaver.autosaveNow().ok());
    ASSERT_TRUE(fs::exists(autosavePath(file)));
    doc->undoStack()->undo();
    doc->undoStack()->undo();
    ASSERT_FALSE(doc->isDirty());
    ASSERT_TRUE(autosaver.autosaveNow().ok());
    EXPECT_FALSE(fs::exists(autosavePath(file)));
}

TEST(Autosave, SaveAsRetiresTheAutosaveBesideTheOldFile) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    const fs::path oldFile = doc->filePath();
    Autosaver autosaver(doc.get());
    ASSERT_TRUE(doc->setName("renamed").ok());
    ASSERT_TRUE(autosaver.autosaveNow().ok());
    ASSERT_TRUE(fs::exists(autosavePath(oldFile)));
    ASSERT_TRUE(doc->saveAs(dir / "copy.frayproj").ok());
    EXPECT_FALSE(fs::exists(autosavePath(oldFile)));
    EXPECT_FALSE(fs::exists(autosavePath(dir / "copy.frayproj")));
    // The next autosave goes beside the new file.
    ASSERT_TRUE(doc->setName("renamed again").ok());
    ASSERT_TRUE(autosaver.autosaveNow().ok());
    EXPECT_TRUE(fs::exists(autosavePath(dir / "copy.frayproj")));
    EXPECT_FALSE(fs::exists(autosavePath(oldFile)));
}

TEST(Autosave, AFailedAutosaveIsReportedAndTouchesNothing) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    const fs::path file = doc->filePath();
    const std::string onDisk = test::readFile(file);
    fs::create_directories(autosavePath(file) / "blocker");  // the autosave's place is taken
    Autosaver autosaver(doc.get());
    QString reported;
    QObject::connect(&autosaver, &Autosaver::failed, [&](const QString& why) { reported = why; });
    ASSERT_TRUE(doc->setName("unsaved").ok());
    const Status st = autosaver.autosaveNow();
    ASSERT_FALSE(st.ok());
    EXPECT_NE(st.error().message.find("demo.frayproj.autosave"), std::string::npos) << st.error().message;
    EXPECT_TRUE(reported.contains(QStringLiteral("demo.frayproj.autosave"))) << reported.toStdString();
    EXPECT_EQ(test::readFile(file), onDisk);
    EXPECT_TRUE(doc->isDirty());
}

TEST(Autosave, ABrokenAutosaveIsAClearError) {
    test::TempDir dir;
    const fs::path file = dir / "p.frayproj";
    fs::copy_file(test::demoProject(), file);
    std::string text = test::readFile(file);
    text.replace(text.find("\"frame_count\": "), 16, "\"frame_count\": -");
    {
        std::ofstream(autosavePath(file), std::ios::binary) << text;
    }
    touchAfter(autosavePath(file), file, 5);
    const auto recovery = findRecovery(file);
    ASSERT_TRUE(recovery.has_value());
    const auto r = recoverDocument(*recovery);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("p.frayproj.autosave: /motions/0/frame_count"), std::string::npos)
        << r.error().message;

    // An autosave whose project is gone is still offered.
    fs::remove(file);
    ASSERT_TRUE(findRecovery(file).has_value());
}

TEST(Autosave, TheTimerWritesAtTheIntervalAndZeroTurnsItOff) {
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    Autosaver autosaver(doc.get());
    int writes = 0;
    QObject::connect(&autosaver, &Autosaver::autosaved, [&] { ++writes; });
    ASSERT_TRUE(doc->setName("timed").ok());

    autosaver.setIntervalSeconds(0);
    QEventLoop loop;
    QTimer::singleShot(1300, &loop, &QEventLoop::quit);
    loop.exec();
    EXPECT_EQ(writes, 0);
    EXPECT_FALSE(fs::exists(autosavePath(doc->filePath())));

    autosaver.setIntervalSeconds(1);
    QTimer::singleShot(1600, &loop, &QEventLoop::quit);
    loop.exec();
    EXPECT_EQ(writes, 1) << "one write per change, however many ticks";
    EXPECT_EQ(test::readFile(autosavePath(doc->filePath())), doc->serialized());
}

TEST(Autosave, IntervalIsASetting) {
    test::TempDir dir;
    QSettings settings(QString::fromStdString((dir / "fray.ini").string()), QSettings::IniFormat);
    EXPECT_EQ(Autosaver::intervalFromSettings(settings), 120);
    Autosaver::storeInterval(settings, 30);
    EXPECT_EQ(Autosaver::intervalFromSettings(settings), 30);
    settings.setValue("autosave/interval_seconds", "often");
    EXPECT_EQ(Autosaver::intervalFromSettings(settings), 120);
}

TEST(RecentFiles, MostRecentFirstWithoutRepeatsAtLeastTen) {
    test::TempDir dir;
    QSettings settings(QString::fromStdString((dir / "fray.ini").string()), QSettings::IniFormat);
    RecentFiles recent(settings);
    EXPECT_EQ(recent.capacity(), 10);
    std::vector<QString> files;
    for (int i = 0; i < 12; ++i) {
        const fs::path f = dir / ("p" + std::to_string(i) + ".frayproj");
        std::ofstream(f) << "{}";
        files.push_back(QString::fromStdString(f.string()));
        recent.add(files.back());
    }
    QStringList list = recent.files();
    ASSERT_EQ(list.size(), 10);
    EXPECT_EQ(list.front(), RecentFiles::normalized(files[11]));
    EXPECT_EQ(list.back(), RecentFiles::normalized(files[2]));

    // The same file by another spelling moves to the front, not in twice.
    recent.add(QString::fromStdString((dir / "." / "p5.frayproj").string()));
    list = recent.files();
    EXPECT_EQ(list.size(), 10);
    EXPECT_EQ(list.front(), RecentFiles::normalized(files[5]));
    EXPECT_EQ(list.count(RecentFiles::normalized(files[5])), 1);

    // Kept in the settings: a new list over the same settings sees it.
    RecentFiles reopened(settings);
    EXPECT_EQ(reopened.files(), list);

    // Missing files are flagged, then pruned.
    fs::remove(dir / "p7.frayproj");
    fs::remove(dir / "p9.frayproj");
    int missing = 0;
    for (const auto& e : recent.entries()) missing += e.exists ? 0 : 1;
    EXPECT_EQ(missing, 2);
    EXPECT_EQ(recent.prune(), 2);
    EXPECT_EQ(recent.files().size(), 8);
    EXPECT_FALSE(recent.files().contains(RecentFiles::normalized(files[7])));

    recent.setCapacity(30);
    for (const auto& f : files) recent.add(f);
    EXPECT_EQ(recent.files().size(), 12);
    recent.setCapacity(3);
    EXPECT_EQ(recent.files().size(), 3);
    recent.remove(files[11]);
    EXPECT_EQ(recent.files().size(), 2);
    recent.clear();
    EXPECT_TRUE(recent.files().isEmpty());
}
