#pragma once
// The editor's main window opened the way `fray P.frayproj` opens it, but
// offscreen and without a Vulkan viewport, for the window tests: the
// project's takes loaded, the saved layout ignored, autosave off.
#include <gtest/gtest.h>

#include <QString>
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

}  // namespace fray::test
