#pragma once
// Scene setups (issue 23): everything the user authors for a scene, stored in
// the project file's "scene" section instead of loose --spec JSON and PNG
// files. A setup is named and has a kind; its parameters are kept as a JSON
// object in the very format of a --spec file (docs/SIM.md, docs/PATCHES.md),
// in the order and with the number spellings they were written in, so that a
// setup imported from a spec file plans the same scene bytes as --spec on
// that file. Around it the setup holds what a spec file cannot: trajectories
// as their defining shapes (polyline, arc, circle) with checkpoints, the
// painted floor bitmap (stored losslessly in the project, docs/FILES.md),
// pins of edited generated interactions and the keep/reject verdicts of
// Interaction Patches.
//
// Typed accessors read and write the parts the editor's tools touch (start
// placements, teams, the rat's trajectory, football directions, timed
// commands, domino starts); setParameter edits any other field by JSON
// pointer. Plain C++20, no Qt (core/setup, target fray_setup).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fray/core/result.h"
#include "fray/prep/project.h"
#include "fray/sim/scene.h"

namespace fray::setup {

inline constexpr const char* kSetupSection = "scene";
// Section version 1; 2 when a setup of an Interaction Graph kind is in it
// (so a build from before them says the version is not supported instead of
// naming a kind it does not know); both are read. The floor's "data" is packed bits since f5a5a8a; a
// project saved by the very first setups commit (one byte a pixel) reads as
// damaged floor data: import the bitmap again.

// duel and chase are planned by tree expansion (fray-cli simulate); the
// graph kinds are played by the Interaction Graph (fray-cli simulate, as
// `igraph play`; fray/setup/graph_setup.h); the others are composed from
// Interaction Patches (fray-cli compose).
enum class SetupKind { Duel, Chase, OneVsMany, OneVsOne, Domino, Luggage, Football, Rat, GraphDuel, GraphTeams, GraphCarry };
// duel, chase, one-vs-many, one-vs-one, domino, luggage, football, rat, graph-duel, graph-teams, graph-carry
const char* setupKindName(SetupKind kind);
std::optional<SetupKind> setupKindFromName(std::string_view name);
const std::vector<SetupKind>& allSetupKinds();
inline bool isTreeExpansion(SetupKind k) { return k == SetupKind::Duel || k == SetupKind::Chase; }
// Run by `fray-cli simulate --setup` (tree expansion and the Interaction
// Graph); the others by `fray-cli compose --setup`.
inline bool isSimulateKind(SetupKind k) { return isTreeExpansion(k) || k == SetupKind::GraphDuel || k == SetupKind::GraphTeams || k == SetupKind::GraphCarry; }

struct Point {
    double x = 0, z = 0;
    friend bool operator==(const Point&, const Point&) = default;
};

// A start placement (the spec's {x, z, heading_deg}).
struct Placement {
    double x = 0, z = 0, headingDeg = 0;
    friend bool operator==(const Placement&, const Placement&) = default;
};

// A checkpoint on a trajectory: reached within the spec's checkpoint radius,
// not before `time` when set, playing `action` ("@annotation" or an action
// name) there when set.
struct SetupCheckpoint {
    Point pos;
    std::optional<double> time;
    std::string action;
    friend bool operator==(const SetupCheckpoint&, const SetupCheckpoint&) = default;
};

enum class TrajectoryShape { Polyline, Arc, Circle };
const char* trajectoryShapeName(TrajectoryShape shape);  // polyline, arc, circle

// A character's trajectory, stored as its defining points:
//   polyline: the vertices (at least 1);
//   arc:      start, a point it passes through, end (3 points);
//   circle:   centre and a point on the circle, where it starts (2 points),
//             run counter-clockwise seen from above (+Y) unless `clockwise`.
// Checkpoints are kept in the order they are passed along the trajectory.
struct Trajectory {
    std::string character;  // the character (spec "name") who follows it
    TrajectoryShape shape = TrajectoryShape::Polyline;
    std::vector<Point> points;
    bool clockwise = false;  // circle only
    bool loop = false;       // start over at the end (a circle loops by nature when set)
    std::vector<SetupCheckpoint> checkpoints;
    friend bool operator==(const Trajectory&, const Trajectory&) = default;
};

// The painted floor (domino): a 1-bit bitmap laid on the floor with pixel
// (0, 0) at `origin` (x, z) and +x, +z along its rows and columns.
struct FloorPaint {
    int width = 0, height = 0;
    double metresPerPixel = 0.1;
    Point origin;
    std::vector<std::uint8_t> painted;  // row-major, 0 or 1
    bool empty() const { return width <= 0 || height <= 0; }
    std::uint8_t at(int x, int y) const { return painted[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)]; }
    friend bool operator==(const FloorPaint&, const FloorPaint&) = default;
};
inline constexpr int kMaxFloorPixels = 4096;  // per side

// An edited generated interaction: `character` plays `action` (a library
// action name) from `time` s; a re-plan keeps it.
struct Pin {
    std::string character;
    double time = 0;
    std::string action;
    friend bool operator==(const Pin&, const Pin&) = default;
};

// Verdicts on the patches of the project's patch library (indices as listed
// by `fray-cli patches list`); rejected patches never compose.
struct PatchVerdicts {
    std::vector<int> kept, rejected;  // ascending, disjoint
    friend bool operator==(const PatchVerdicts&, const PatchVerdicts&) = default;
};

struct SceneSetup {
    std::string name;
    SetupKind kind = SetupKind::Duel;
    // The parameters: a JSON object in the --spec format of the kind
    // (without "kind", which is the field above). For compose kinds the
    // floor's "bitmap" field, when present, only records the file the
    // bitmap was imported from: the pixels are `floor`.
    std::string spec = "{}";
    std::vector<Trajectory> trajectories;
    std::optional<FloorPaint> floor;
    std::vector<Pin> pins;
    PatchVerdicts patches;
    friend bool operator==(const SceneSetup&, const SceneSetup&) = default;
};

// ---- the project's section ----------------------------------------------------
// Reads the project's setups (absent section: none). Errors name the file
// and the JSON path ("demo.frayproj: /scene/setups/1/floor/width: must be ...").
Result<std::vector<SceneSetup>> projectSetups(const prep::Project& project, std::string_view fileName);
// Writes the setups into the project's section (none: the section is removed).
void setProjectSetups(prep::Project& project, const std::vector<SceneSetup>& setups);
// The section's JSON text for these setups (what setProjectSetups stores).
std::string setupsToJson(const std::vector<SceneSetup>& setups);
// Checks one setup the way the reader does (names, kind, spec object,
// trajectory shapes, bitmap size, pins, verdicts); `path` prefixes errors.
Status checkSetup(const SceneSetup& setup, std::string_view fileName, const std::string& path);
// A setup name: 1-64 characters, UTF-8, no control characters.
Status checkSetupName(std::string_view name);

const SceneSetup* findSetup(const std::vector<SceneSetup>& setups, std::string_view name);
SceneSetup* findSetup(std::vector<SceneSetup>& setups, std::string_view name);

// A new setup of a kind with the parameters of its demo (duel: two boxers
// 1.1 m apart; chase: two chasers and a runaway; domino: an empty 20 x 12 m
// floor at 0.1 m per pixel; ...).
SceneSetup makeSetup(std::string name, SetupKind kind);

// ---- typed access to the parameters -----------------------------------------
// Characters of a tree-expansion setup (the spec's "characters").
struct SetupCharacter {
    std::string name;
    int side = 0;             // team
    std::string preset;       // "" : the default (general-boxer)
    int depth = 3;
    Placement start;
    friend bool operator==(const SetupCharacter&, const SetupCharacter&) = default;
};
std::vector<SetupCharacter> characters(const SceneSetup& setup);
int characterIndex(const SceneSetup& setup, std::string_view name);  // -1 when absent
// Moves one character's start; a team move moves every character of a side by
// the same offset (headings kept). Errors name the setup and the character.
Status setCharacterStart(SceneSetup& setup, std::string_view character, const Placement& start);
Status moveTeam(SceneSetup& setup, int side, double dx, double dz);

// Compose kinds' inputs.
std::vector<Point> ratPath(const SceneSetup& setup);                 // the rat's "rat"/"path"
Status setRatPath(SceneSetup& setup, const std::vector<Point>& path);
// `at`: where the arrow was drawn on the floor (the spec's optional "at":
// [x, z]); composing reads only the time and the heading.
struct RunDirection {
    double time = 0, headingDeg = 0;
    std::optional<Point> at = std::nullopt;
    friend bool operator==(const RunDirection&, const RunDirection&) = default;
};
std::vector<RunDirection> runDirections(const SceneSetup& setup);   // football "directions"
Status setRunDirections(SceneSetup& setup, const std::vector<RunDirection>& directions);
// `at`: where the command was placed on the floor (the spec's "at": [x, z]);
// a move command needs it (the main character walks there), the others keep
// it to show where they were placed.
struct TimedCommand {
    double time = 0;
    std::string action;  // move, punch, kick, avoid (also attack, defence, block)
    std::optional<Point> at = std::nullopt;
    friend bool operator==(const TimedCommand&, const TimedCommand&) = default;
};
std::vector<TimedCommand> timedCommands(const SceneSetup& setup);    // one-vs-many "commands"
Status setTimedCommands(SceneSetup& setup, const std::vector<TimedCommand>& commands);
struct DominoStartPoint {
    double time = 0;
    Point pos;
    friend bool operator==(const DominoStartPoint&, const DominoStartPoint&) = default;
};
std::vector<DominoStartPoint> dominoStarts(const SceneSetup& setup); // domino "starts"
Status setDominoStarts(SceneSetup& setup, const std::vector<DominoStartPoint>& starts);

// Any parameter by JSON pointer ("/duration", "/characters/1/depth",
// "/characters/0/weights/r_d"), `value` a JSON text; null removes the field.
// Missing parents are created. The pointer may not reach "kind".
Status setParameter(SceneSetup& setup, std::string_view pointer, std::string_view value);
// The value at a pointer as JSON text, or nullopt.
std::optional<std::string> parameter(const SceneSetup& setup, std::string_view pointer);

// ---- trajectories --------------------------------------------------------------
// The trajectory's centre line sampled every `spacing` m (its first point
// first; a loop does not repeat it). Errors: too few points, an arc whose
// three points are on a line, a circle of zero radius.
Result<std::vector<Point>> sampleTrajectory(const Trajectory& t, double spacing = 0.5);
// The distance along the sampled line of the point nearest to `p` (to order
// checkpoints and to insert them).
double trajectoryParameter(const std::vector<Point>& line, Point p, double* distance = nullptr);

// ---- bitmap --------------------------------------------------------------------
// The painted floor's scale, metres per pixel in (0.001, 10] as compose reads
// it: the pixels stay, pixel (0, 0) stays at the floor's origin, so the
// painting grows or shrinks away from that corner, and a domino's chain
// starts move with it (each stays on its pixel); the spec's
// "floor"/"metres_per_pixel", when stored, follows. Errors name the setup.
Status setFloorScale(SceneSetup& setup, double metresPerPixel);
sim::FloorBitmap toFloorBitmap(const FloorPaint& paint);
FloorPaint fromFloorBitmap(const sim::FloorBitmap& floor);
// Lossless text form kept in the project: the pixels packed eight to a byte
// (first pixel in the high bit, row after row), zlib (level 6), base64
// (docs/FILES.md).
std::string encodeFloor(const FloorPaint& paint);
Result<FloorPaint> decodeFloor(std::string_view data, int width, int height, std::string_view what);

}  // namespace fray::setup
