#pragma once
// The editor's main window opened the way `fray P.frayproj` opens it, but
// offscreen and without a Vulkan viewport, for the window tests: the
// project's takes loaded, the saved layout ignored, autosave off.
#include <gtest/gtest.h>

#include <QObject>
#include <QString>
#include <QTemporaryDir>
#include <filesystem>
#include <memory>

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

}  // namespace fray::test
