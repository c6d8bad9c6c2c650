#pragma once
// The demo project the build writes, opened as a document in a scratch folder.
#include <gtest/gtest.h>

#include <QUndoStack>

#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <string>

#include "fray/authoring/project_document.h"
#include "fray/prep/project.h"
#include "temp_dir.h"

namespace fray::test {

inline std::filesystem::path demoProject() { return FRAY_DEMO_PROJECT; }

inline std::string readFile(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// A copy of the demo project in `dir`, opened.
inline std::unique_ptr<authoring::ProjectDocument> openDemoCopy(const TempDir& dir,
                                                                const std::string& name = "demo.frayproj") {
    const auto target = dir / name;
    std::filesystem::copy_file(demoProject(), target, std::filesystem::copy_options::overwrite_existing);
    auto doc = authoring::ProjectDocument::open(target);
    if (!doc) {
        ADD_FAILURE() << doc.error().message;
        return nullptr;
    }
    return std::move(*doc);
}

// Applies `edit`, which must push exactly one command, then checks that undo
// gives back the bytes from before and redo the bytes from after, and that
// the document stays a loadable project (vocabulary, cuts and actions agree);
// `reloaded` (when given) checks more of the project loaded from those bytes.
inline void expectOneUndoableStep(authoring::ProjectDocument& doc, const std::string& what, const std::function<Status()>& edit,
                                  const std::function<void(const prep::Project&)>& reloaded = {}) {
    SCOPED_TRACE(what);
    const std::string before = doc.serialized();
    const int count = doc.undoStack()->count();
    const Status st = edit();
    ASSERT_TRUE(st.ok()) << st.error().message;
    ASSERT_EQ(doc.undoStack()->count(), count + 1) << "the edit must push one command";
    const std::string after = doc.serialized();
    EXPECT_NE(after, before) << "the edit changed nothing";
    doc.undoStack()->undo();
    EXPECT_EQ(doc.serialized(), before);
    doc.undoStack()->redo();
    EXPECT_EQ(doc.serialized(), after);
    const auto project = prep::projectFromJson(after, "after.frayproj");
    ASSERT_TRUE(project.ok()) << project.error().message;
    if (reloaded) reloaded(*project);
}

}  // namespace fray::test
