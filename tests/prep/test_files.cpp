// File safety (docs/FILES.md): atomic saves through links and with the
// original's permissions, concurrent savers, the project lock, bounded reads
// and JSON documents, the cache checksum, and the checks at the edges
// (suitabilities, annotations, CSV text).
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "fray/core/atomic_file.h"
#include "fray/prep/combos.h"
#include "fray/prep/json_reader.h"
#include "fray/prep/labels.h"
#include "fray/prep/pipeline.h"
#include "fray/prep/project.h"
#include "temp_dir.h"

using namespace fray;
using namespace fray::prep;
namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

// Issue 21 item 2: every save used path + ".tmp", so two savers wrote into one
// temporary and renamed it from under each other.
TEST(AtomicFile, ConcurrentSaversNeverShareATemporary) {
    fray::test::TempDir dir;
    const fs::path file = dir / "f.txt";
    const std::string a(200000, 'a'), b(300000, 'b');
    std::atomic<int> errors{0};
    std::atomic<bool> torn{false};
    auto writer = [&](const std::string& text) {
        for (int i = 0; i < 200; ++i) {
            if (!writeFileAtomically(file, text).ok()) ++errors;
        }
    };
    auto reader = [&] {
        for (int i = 0; i < 400; ++i) {
            const std::string now = slurp(file);
            if (!now.empty() && now != a && now != b) torn = true;
        }
    };
    ASSERT_TRUE(writeFileAtomically(file, a).ok());
    std::thread t1(writer, a), t2(writer, b), t3(reader);
    t1.join();
    t2.join();
    t3.join();
    EXPECT_EQ(errors.load(), 0);
    EXPECT_FALSE(torn.load());
    const std::string last = slurp(file);
    EXPECT_TRUE(last == a || last == b);
    for (const auto& e : fs::directory_iterator(dir.path())) EXPECT_EQ(e.path().filename(), "f.txt");
}

// Item 7: saving through a symbolic link replaced the link with a copy.
TEST(AtomicFile, SymlinkTargetIsReplacedAndTheLinkKept) {
    fray::test::TempDir dir;
    fs::create_directories(dir / "real");
    ASSERT_TRUE(writeFileAtomically(dir / "real" / "p.frayproj", "old").ok());
    fs::create_symlink("real/p.frayproj", dir / "link.frayproj");
    ASSERT_TRUE(writeFileAtomically(dir / "link.frayproj", "new").ok());
    EXPECT_TRUE(fs::is_symlink(dir / "link.frayproj"));
    EXPECT_EQ(slurp(dir / "real" / "p.frayproj"), "new");
    EXPECT_EQ(resolveWriteTarget(dir / "link.frayproj"), dir / "real/p.frayproj");
}

// Item 7: mode 600 became 644.
TEST(AtomicFile, PermissionsAreKept) {
    fray::test::TempDir dir;
    const fs::path file = dir / "secret.frayproj";
    ASSERT_TRUE(writeFileAtomically(file, "v1").ok());
    fs::permissions(file, fs::perms::owner_read | fs::perms::owner_write, fs::perm_options::replace);
    ASSERT_TRUE(writeFileAtomically(file, "v2").ok());
    EXPECT_EQ(fs::status(file).permissions() & fs::perms::all, fs::perms::owner_read | fs::perms::owner_write);
    EXPECT_EQ(slurp(file), "v2");
}

// The documented choice for hard links: the saved name gets the new
// contents, other names keep the old file (renaming is what makes it atomic).
TEST(AtomicFile, HardLinksAreSplitAsDocumented) {
    fray::test::TempDir dir;
    ASSERT_TRUE(writeFileAtomically(dir / "a", "old").ok());
    fs::create_hard_link(dir / "a", dir / "b");
    ASSERT_TRUE(writeFileAtomically(dir / "a", "new").ok());
    EXPECT_EQ(slurp(dir / "a"), "new");
    EXPECT_EQ(slurp(dir / "b"), "old");
}

TEST(AtomicFile, RefusesToReplaceAFolder) {
    fray::test::TempDir dir;
    fs::create_directories(dir / "x");
    const auto st = writeFileAtomically(dir / "x", "data");
    ASSERT_FALSE(st.ok());
    EXPECT_TRUE(contains(st.error().message, "not a regular file")) << st.error().message;
    EXPECT_TRUE(fs::is_directory(dir / "x"));
}

// Item 13: /dev/zero was read without end; a device is refused at once.
TEST(ReadWholeFile, RefusesDevicesAndBoundsTheSize) {
    const auto zero = readWholeFile("/dev/zero", "the project file");
    ASSERT_FALSE(zero.ok());
    EXPECT_TRUE(contains(zero.error().message, "/dev/zero: cannot open the project file: not a regular file"))
        << zero.error().message;
    fray::test::TempDir dir;
    ASSERT_TRUE(writeFileAtomically(dir / "big", std::string(5000, 'x')).ok());
    const auto big = readWholeFile(dir / "big", "the scene file", 4096);
    ASSERT_FALSE(big.ok());
    EXPECT_TRUE(contains(big.error().message, "more than the limit of 4096")) << big.error().message;
    EXPECT_EQ(readWholeFile(dir / "big", "x", 5000).value().size(), 5000u);
    EXPECT_TRUE(contains(readWholeFile(dir / "none", "the cache").error().message, "no such file"));
}

TEST(FileLock, SecondHolderWaitsThenGivesUpWithAMessage) {
    fray::test::TempDir dir;
    const fs::path file = dir / "p.frayproj";
    auto first = FileLock::acquire(file);
    ASSERT_TRUE(first.ok()) << first.error().message;
    EXPECT_TRUE(fs::exists(dir / "p.frayproj.lock"));
    const auto t0 = std::chrono::steady_clock::now();
    auto second = FileLock::acquire(file, std::chrono::milliseconds(100));
    ASSERT_FALSE(second.ok());
    EXPECT_GE(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(100));
    EXPECT_TRUE(contains(second.error().message, "another program is still editing it")) << second.error().message;
    { FileLock released = std::move(*first); }
    EXPECT_TRUE(FileLock::acquire(file, std::chrono::milliseconds(100)).ok());
}

// Item 1: a project nested 100,000 levels deep crashed every verb (stack
// overflow in a recursive copy).
TEST(Json, DeepNestingIsRefusedWithLineAndColumn) {
    std::string text = "{\"format\": \"fray-project\", \"version\": 1, \"motions\": [],\n\"paintings\": ";
    text += std::string(100000, '[') + std::string(100000, ']') + "}";
    const auto p = projectFromJson(text, "deep.frayproj");
    ASSERT_FALSE(p.ok());
    EXPECT_TRUE(contains(p.error().message, "deep.frayproj:2:")) << p.error().message;
    EXPECT_TRUE(contains(p.error().message, "nested deeper than 64 levels")) << p.error().message;
    // Brackets inside strings do not count; 64 levels are fine.
    EXPECT_TRUE(parseJson("[\"" + std::string(1000, '[') + "\"]", "s.json").ok());
    EXPECT_TRUE(parseJson(std::string(64, '[') + std::string(64, ']'), "ok.json").ok());
    EXPECT_FALSE(parseJson(std::string(65, '[') + std::string(65, ']'), "no.json").ok());
}

// Item 13: syntax errors give the line and the column.
TEST(Json, SyntaxErrorsNameLineAndColumn) {
    const auto r = parseJson("{\n  \"a\": 1,\n  \"b\": tru\n}", "spec.json");
    ASSERT_FALSE(r.ok());
    EXPECT_TRUE(contains(r.error().message, "spec.json:3:")) << r.error().message;
    EXPECT_TRUE(contains(r.error().message, "not valid JSON")) << r.error().message;
    const auto big = parseJson("[1e999]", "n.json");
    ASSERT_FALSE(big.ok());
    EXPECT_TRUE(contains(big.error().message, "n.json")) << big.error().message;
}

TEST(Json, Utf8CheckAndDumpNeverThrows) {
    EXPECT_TRUE(isValidUtf8("plain"));
    EXPECT_TRUE(isValidUtf8("caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80"));
    EXPECT_FALSE(isValidUtf8("caf\xE9"));
    EXPECT_FALSE(isValidUtf8("\xC0\xAF"));          // overlong
    EXPECT_FALSE(isValidUtf8("\xED\xA0\x80"));      // surrogate
    EXPECT_FALSE(isValidUtf8("\xE2\x82"));          // truncated
    nlohmann::ordered_json j;
    j["joint"] = std::string("Hanche_\xE9");
    std::string out;
    EXPECT_NO_THROW(out = dumpJson(j));
    EXPECT_TRUE(parseJson(out, "x").ok());
}

// Item 10 (project part): a Latin-1 joint name from a capture used to make
// every save throw type_error.316.
TEST(Project, NonUtf8NamesDoNotBreakTheSave) {
    Project p = makeProject("demo");
    ProjectMotion m;
    m.id = "walk";
    m.path = "walk.bvh";
    m.actions = MotionActions::whole(10);
    m.actions.actions[0].joints = {std::string("Epaule_\xE9")};
    p.motions.push_back(m);
    std::string text;
    ASSERT_NO_THROW(text = projectToJson(p));
    EXPECT_TRUE(projectFromJson(text, "p.frayproj").ok());
}

// Item 4: NaN suitabilities were written as null and then refused by every
// verb; now nothing non-finite gets in, and a null is refused with its path.
TEST(Combos, RecordsAreCheckedAtTheEdge) {
    const std::vector<std::string> vocab = {"punch", "block"};
    EXPECT_TRUE(ComboTable::checkRecord({"jab", "@block", 1.5}, vocab).ok());
    for (double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL, 2e6}) {
        const auto st = ComboTable::checkRecord({"jab", "@block", bad}, vocab);
        ASSERT_FALSE(st.ok()) << bad;
        EXPECT_TRUE(contains(st.error().message, "suitability")) << st.error().message;
    }
    // Item 12: annotations not in the vocabulary (@flyingkick, @pnuch).
    const auto st = ComboTable::checkRecord({"@flyingkick", "@pnuch", 1}, vocab);
    ASSERT_FALSE(st.ok());
    EXPECT_TRUE(contains(st.error().message, "mine: @flyingkick is not in the project vocabulary (punch, block)"))
        << st.error().message;
    const auto csv = ComboTable::fromCsv("mine,theirs,suitability\njab,@pnuch,1\n", "c.csv", &vocab);
    ASSERT_FALSE(csv.ok());
    EXPECT_TRUE(contains(csv.error().message, "c.csv:2: theirs: @pnuch")) << csv.error().message;

    const std::string nullSuit = R"({"format": "fray-project", "version": 1, "motions": [],
        "combos": [{"mine": "jab", "theirs": "@block", "suitability": null}]})";
    const auto p = projectFromJson(nullSuit, "p.frayproj");
    ASSERT_FALSE(p.ok());
    EXPECT_TRUE(contains(p.error().message, "p.frayproj: /combos/0/suitability: must be a number")) << p.error().message;
}

// Item 13: a UTF-8 byte-order mark was refused; binary content was echoed.
TEST(Csv, ByteOrderMarkAcceptedAndBinaryNeverEchoed) {
    const auto rows = parseLabelsCsv("\xEF\xBB\xBFmotion,first_frame,last_frame,left,right\nwalk,0,10,1,0\n", "l.csv");
    ASSERT_TRUE(rows.ok()) << rows.error().message;
    EXPECT_EQ(rows->size(), 1u);
    const auto table = ComboTable::fromCsv("\xEF\xBB\xBFmine,theirs,suitability\njab,duck,1\n", "c.csv");
    ASSERT_TRUE(table.ok()) << table.error().message;

    const auto bin = parseLabelsCsv(std::string("\x7F" "ELF\x02\x01\x01\0\0\0", 10), "l.csv");
    ASSERT_FALSE(bin.ok());
    EXPECT_EQ(bin.error().message, "l.csv: is not a text file (it contains NUL bytes)");
    const auto esc = parseLabelsCsv("motion,first_frame,last_frame,left,right\nwalk,\x1B[2J\xFF,3,1,0\n", "l.csv");
    ASSERT_FALSE(esc.ok());
    EXPECT_FALSE(contains(esc.error().message, "\x1B")) << esc.error().message;
    EXPECT_FALSE(contains(esc.error().message, "\xFF")) << esc.error().message;
    EXPECT_TRUE(contains(esc.error().message, "l.csv:2: first_frame")) << esc.error().message;
}

// Item 6: one flipped bit changed the cached segmentation and graph and was
// reported as "(cached)". Every single-bit change is now caught.
TEST(Cache, EveryFlippedBitIsCaught) {
    DerivedCache c;
    CachedContacts cc;
    cc.key = 42;
    cc.contacts.left = {1, 0, 1, 1, 0};
    cc.contacts.right = {0, 0, 1, 0, 1};
    c.contacts.emplace_back("walk", cc);
    c.graph = CachedGraph{7, 3, {0, 1, 2}, {1, 2, 0}};
    const auto bytes = serializeCache(c);
    ASSERT_TRUE(deserializeCache(bytes).ok());
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        for (int bit = 0; bit < 8; ++bit) {
            auto flipped = bytes;
            flipped[i] = static_cast<std::uint8_t>(flipped[i] ^ (1u << bit));
            EXPECT_FALSE(deserializeCache(flipped).ok()) << "byte " << i << " bit " << bit;
        }
    }
}

TEST(Cache, DamagedFileReadsAsEmptyAndSaysSo) {
    fray::test::TempDir dir;
    const fs::path project = dir / "p.frayproj";
    DerivedCache c;
    c.graph = CachedGraph{7, 3, {0, 1, 2}, {1, 2, 0}};
    ASSERT_TRUE(writeCache(project, c).ok());
    std::string why;
    bool damaged = true;
    EXPECT_TRUE(readCache(project, &why, &damaged).graph.has_value());
    EXPECT_FALSE(damaged);
    auto bytes = slurp(cachePath(project));
    bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 4);
    ASSERT_TRUE(writeFileAtomically(cachePath(project), bytes).ok());
    EXPECT_FALSE(readCache(project, &why, &damaged).graph.has_value());
    EXPECT_TRUE(damaged);
    EXPECT_TRUE(contains(why, "checksum mismatch")) << why;
    fs::remove(cachePath(project));
    (void)readCache(project, &why, &damaged);
    EXPECT_FALSE(damaged);
}
