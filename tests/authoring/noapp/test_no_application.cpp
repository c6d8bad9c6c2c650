// The document without any Q*Application: what a command-line tool gets.
#include <gtest/gtest.h>

#include <QCoreApplication>

#include "document_fixture.h"
#include "fray/authoring/autosave.h"
#include "fray/authoring/project_document.h"

using namespace fray;
namespace fs = std::filesystem;

TEST(NoApplication, EditUndoSaveAndRecoverWork) {
    ASSERT_EQ(QCoreApplication::instance(), nullptr);
    test::TempDir dir;
    auto doc = test::openDemoCopy(dir);
    ASSERT_TRUE(doc);
    const std::string start = doc->serialized();
    const std::string box = "shadowbox_energetic";
    const int cut = doc->project().findMotion(box)->actions.cuts[0];
    ASSERT_TRUE(doc->setActionName(box, 0, "opening_jab").ok());
    ASSERT_TRUE(doc->moveCut(box, cut, cut + 2).ok());
    ASSERT_TRUE(doc->addVocabularyWord("feint").ok());
    EXPECT_TRUE(doc->isDirty());
    const std::string edited = doc->serialized();
    ASSERT_TRUE(doc->save().ok());
    EXPECT_FALSE(doc->isDirty());
    EXPECT_EQ(test::readFile(doc->filePath()), edited);
    while (doc->undoStack()->canUndo()) doc->undoStack()->undo();
    EXPECT_EQ(doc->serialized(), start);

    // An explicit autosave (no timer runs without an event loop) and its recovery.
    authoring::Autosaver autosaver(doc.get());
    ASSERT_TRUE(autosaver.autosaveNow().ok());
    fs::last_write_time(authoring::autosavePath(doc->filePath()),
                        fs::last_write_time(doc->filePath()) + std::chrono::seconds(5));
    const auto recovery = authoring::findRecovery(doc->filePath());
    ASSERT_TRUE(recovery.has_value());
    auto recovered = authoring::recoverDocument(*recovery);
    ASSERT_TRUE(recovered.ok()) << recovered.error().message;
    EXPECT_EQ((*recovered)->serialized(), start);
}
