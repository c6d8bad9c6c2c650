#pragma once
// The editor's main window opened the way `fray P.frayproj` opens it, but
// offscreen and without a Vulkan viewport, for the window tests: the
// project's takes loaded, the saved layout ignored, autosave off.
#include <gtest/gtest.h>

#include <QApplication>
#include <QObject>
#include <QString>
#include <QTest>
#include <QStyleOptionViewItem>
#include <QStyle>
#include <QListWidget>
#include <QTemporaryDir>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>

#include "main_window.h"
#include "takes.h"

namespace fray::test {

inline std::unique_ptr<editor::MainWindow> openEditorWindow(
    const QString& project, editor::EditorOptions::Recovery recovery = editor::EditorOptions::Recovery::Discard) {
    auto takes = app::loadTakes({project.toStdString()});
    if (!takes) {
        ADD_FAILURE() << takes.error().message;
        return nullptr;
    }
    editor::EditorOptions options;
    options.restoreLayout = false;
    options.autosaveSeconds = 0;
    options.recovery = recovery;
    options.noDialogs = true;
    auto w = std::make_unique<editor::MainWindow>(nullptr, std::move(*takes), nullptr, project, "test", options);
    w->resize(1400, 880);
    w->show();
    return w;
}

// A window test program's main(): the Qt platform (when QT_QPA_PLATFORM is
// unset), the application, then the tests. `instead`, when it returns a
// value, ends the program with it before the tests (a child process's role);
// `after` runs once they have, while the application still exists.
inline int runWindowTests(int argc, char** argv, const char* platform, const std::function<std::optional<int>()>& instead = {},
                          const std::function<void()>& after = {}) {
    if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", platform);
    QApplication app(argc, argv);
    QApplication::setApplicationName("fray-tests");
    if (instead) {
        if (const std::optional<int> code = instead()) return *code;
    }
    ::testing::InitGoogleTest(&argc, argv);
    const int result = RUN_ALL_TESTS();
    if (after) after();
    return result;
}

// The named child widget or object, a test failure when there is none.
template <class T>
T* child(QObject* parent, const char* name) {
    T* found = parent->findChild<T*>(name);
    EXPECT_NE(found, nullptr) << name;
    return found;
}

#ifdef FRAY_DEMO_PROJECT
// A copy of the demo project (takes, project file, contact labels and, unless
// told otherwise, the derived-data cache) in a temporary folder the test owns.
struct DemoCopy {
    QTemporaryDir dir;
    QString project;
    explicit DemoCopy(bool withCache = true) {
        namespace fs = std::filesystem;
        const fs::path from = fs::path(FRAY_DEMO_PROJECT).parent_path();
        for (const auto& entry : fs::directory_iterator(from)) {
            const auto ext = entry.path().extension();
            if (ext == ".bvh" || ext == ".frayproj" || ext == ".csv" || (withCache && ext == ".cache"))
                fs::copy_file(entry.path(), fs::path(dir.path().toStdString()) / entry.path().filename());
        }
        project = dir.filePath("demo.frayproj");
    }
};
#endif

// Clicks the box of a check list's item, as a user does (the space bar plays
// the scene in the editor).
inline bool toggleItem(QListWidget* list, const QString& text) {
    const auto found = list->findItems(text, Qt::MatchExactly);
    if (found.size() != 1) return false;
    list->scrollToItem(found[0]);
    QStyleOptionViewItem opt;
    opt.initFrom(list->viewport());
    opt.rect = list->visualItemRect(found[0]);
    opt.features = QStyleOptionViewItem::HasCheckIndicator | QStyleOptionViewItem::HasDisplay;
    opt.widget = list;
    const QRect box = list->style()->subElementRect(QStyle::SE_ItemViewItemCheckIndicator, &opt, list);
    const Qt::CheckState was = found[0]->checkState();
    QTest::mouseClick(list->viewport(), Qt::LeftButton, {}, box.center());
    // (An edit refreshes the list: find the item again.)
    const auto now = list->findItems(text, Qt::MatchExactly);
    return now.size() == 1 && now[0]->checkState() != was;
}

}  // namespace fray::test
