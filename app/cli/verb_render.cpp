// fray-cli render: offscreen PNG frames of motions (no window, no display).
//
//   render MOTION... --out DIR [--frames A:B:STEP] [--size WxH]
//       frames of one motion, or of several side by side (one colour each)
//   render --contact-sheet MOTION...|PROJECT --out DIR
//       a grid with one cell per motion file, or per action of a project
//
//   render SCENE.frayscene --out DIR [--frames A:B:STEP]
//       a planned scene (frames at 30 per second of scene time): every
//       character posed with transitions, paths and checkpoints, hit flashes
//
//   --rig FILE draws the characters as a skinned rig (glTF/GLB, FBX, ...)
//   instead of capsules; its bones are matched to the joints by name.
//
// Frames come from a motion stage (takes) or from the scene poser (scenes).
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "fray/io/import.h"
#include "fray/prep/project.h"
#include "fray/render/image.h"
#include "fray/render/motion_stage.h"
#include "fray/render/renderer.h"
#include "options.h"
#include "fray/core/kinematics.h"
#include "fray/sim/scene.h"
#include "cli_session.h"
#include "rig_setup.h"
#include "scene_stage.h"
#include "verbs.h"

namespace fray::cli {
namespace {

namespace fs = std::filesystem;
using render::FrameDescription;

struct RenderArgs {
    std::vector<std::string> inputs;
    std::string out;
    std::string frames;
    std::string size = "640x360";
    bool contactSheet = false;
    int columns = 0;
    int maxCells = 16;
    std::string action;
    double yawDeg = 30.0;
    double pitchDeg = 14.0;
    std::string camera = "auto";
    bool trail = false;
    bool labels = false;
    bool noShadows = false;
    bool noGrid = false;
    int msaa = 0;
    bool fast = false;
    bool validate = false;
    bool quiet = false;
    std::string rig;
    std::string posture;  // scenes: kinematic | physics
    bool handPins = false;  // --hand-pins (with --posture physics)
    ImportFlags flags;
};

struct FrameRange {
    int first = 0;
    std::optional<int> last;  // empty: the end
    int step = 1;
};

bool parseInt(std::string_view s, int& out) {
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
    return ec == std::errc() && p == s.data() + s.size();
}

Result<FrameRange> parseFrames(const std::string& spec) {
    FrameRange r;
    if (spec.empty()) return r;
    const std::string bad = "--frames " + spec + ": expected A, A:B or A:B:STEP (frame numbers from 0, B inclusive or 'end')";
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (std::size_t i = 0; i <= spec.size(); ++i)
        if (i == spec.size() || spec[i] == ':') {
            parts.push_back(spec.substr(start, i - start));
            start = i + 1;
        }
    if (parts.size() > 3 || parts[0].empty() || !parseInt(parts[0], r.first) || r.first < 0) return makeError(bad);
    if (parts.size() == 1) {
        r.last = r.first;
        return r;
    }
    if (!parts[1].empty() && parts[1] != "end") {
        int last = 0;
        if (!parseInt(parts[1], last) || last < 0) return makeError(bad);
        if (last < r.first)
            return makeError("--frames " + spec + ": the last frame (" + parts[1] + ") is before the first (" + parts[0] + ")");
        r.last = last;
    }
    if (parts.size() == 3 && (!parseInt(parts[2], r.step) || r.step < 1))
        return makeError("--frames " + spec + ": STEP must be a whole number >= 1");
    return r;
}

Result<std::pair<int, int>> parseSize(const std::string& spec) {
    const auto x = spec.find('x');
    int w = 0, h = 0;
    if (x == std::string::npos || !parseInt(std::string_view(spec).substr(0, x), w) ||
        !parseInt(std::string_view(spec).substr(x + 1), h))
        return makeError("--size " + spec + ": expected WIDTHxHEIGHT, e.g. 1280x720");
    if (w < 16 || h < 16 || w > 8192 || h > 8192) return makeError("--size " + spec + ": each side must be 16..8192 pixels");
    return std::make_pair(w, h);
}

// The cells of a contact sheet, or the characters of one scene: a motion and
// the frame range it plays.
struct Clip {
    std::shared_ptr<Motion> motion;
    std::string name;
    int first = 0, last = 0;
    std::vector<render::ActionSpan> actions;
};

Result<std::vector<Clip>> loadClips(const RenderArgs& a) {
    std::vector<Clip> clips;
    const bool project = a.inputs.size() == 1 && fs::path(a.inputs[0]).extension() == ".frayproj";
    if (project) {
        const fs::path file(a.inputs[0]);
        auto p = prep::loadProject(file);
        if (!p) return p.error();
        for (const prep::ProjectMotion& pm : p->motions) {
            auto m = loadProjectMotion(prep::resolveMotionPath(file, pm), pm);
            if (!m) return m.error();
            auto motion = std::make_shared<Motion>(std::move(*m));
            const auto& acts = pm.actions;
            std::vector<render::ActionSpan> spans;
            for (int i = 0; i < acts.actionCount(); ++i)
                spans.push_back({acts.firstFrame(i), acts.lastFrame(i), acts.actions[static_cast<std::size_t>(i)].name});
            if (!a.contactSheet) {
                clips.push_back({motion, pm.id, 0, motion->frameCount() - 1, spans});
                continue;
            }
            for (int i = 0; i < acts.actionCount(); ++i) {
                const prep::ActionInfo& info = acts.actions[static_cast<std::size_t>(i)];
                // Proposals count too, so they can be reviewed; their cells say so.
                const bool proposed = !a.action.empty() && std::find(info.proposed.begin(), info.proposed.end(),
                                                                     a.action) != info.proposed.end();
                if (!a.action.empty() && info.name != a.action && !info.has(a.action) && !proposed) continue;
                const int last = std::min(acts.lastFrame(i), motion->frameCount() - 1);
                if (acts.firstFrame(i) > last) continue;
                std::string name = info.name.empty() ? pm.id + " #" + std::to_string(i) : info.name;
                if (proposed && info.name != a.action && !info.has(a.action)) name += " (" + a.action + "?)";
                clips.push_back({motion, name, acts.firstFrame(i), last, {}});
            }
        }
        if (clips.empty())
            return makeError(a.inputs[0] + ": no actions to show" + (a.action.empty() ? "" : " named, annotated or proposed '" + a.action + "'"));
    } else {
        auto opts = toLoadOptions(a.flags);
        if (!opts) return opts.error();
        for (const std::string& f : a.inputs) {
            if (fs::path(f).extension() == ".frayproj")
                return makeError(f + ": a project must be the only input (render it alone, or its takes' motion files)");
            auto m = loadMotion(f, *opts);
            if (!m) return m.error();
            if (m->frameCount() == 0) return makeError(f + ": the motion has no frames");
            auto motion = std::make_shared<Motion>(std::move(*m));
            clips.push_back({motion, fs::path(f).stem().string(), 0, motion->frameCount() - 1, {}});
        }
    }
    if (a.contactSheet && static_cast<int>(clips.size()) > a.maxCells) clips.resize(static_cast<std::size_t>(a.maxCells));
    return clips;
}

// Pelvis (or root) position of a motion frame, for centring and following.
glm::vec3 rootAt(const Motion& m, int frame) {
    const auto trail = render::floorTrail(m, frame, frame, 1);
    return trail.empty() ? glm::vec3(0.0f) : trail[0];
}

// The frames of a source: stages of actors posed per output frame.
class MotionSource {
public:
    MotionSource(const std::vector<Clip>& clips, bool sideBySide, bool labels) {
        const int n = static_cast<int>(clips.size());
        for (int i = 0; i < n; ++i) {
            const Clip& c = clips[static_cast<std::size_t>(i)];
            render::StageActor actor;
            actor.motion = c.motion.get();
            actor.name = labels ? c.name : std::string();
            actor.firstFrame = c.first;
            actor.lastFrame = c.last;
            actor.tint = n == 1 ? glm::vec3(0.78f, 0.52f, 0.32f) : render::teamColor(i);
            if (labels) actor.actions = c.actions;
            if (sideBySide && n > 1) {
                // Start every take at its own spot on a line across the view.
                const glm::vec3 start = rootAt(*c.motion, c.first);
                actor.offset = glm::vec3((static_cast<float>(i) - 0.5f * static_cast<float>(n - 1)) * 1.6f - start.x, 0.0f, -start.z);
            }
            stage_.add(std::move(actor));
        }
    }
    render::MotionStage& stage() { return stage_; }
    int frameCount() const { return stage_.longestFrameCount(); }

private:
    render::MotionStage stage_;
};

// Bounds of the stage over frames [first, last] (sampled), for a fixed camera.
render::Bounds boundsOver(render::MotionStage& stage, int first, int last) {
    render::Bounds b;
    const int samples = 24;
    for (int k = 0; k <= samples; ++k) {
        stage.poseFrame(first + (last - first) * k / samples);
        b.add(stage.bounds());
    }
    return b;
}

render::OrbitCamera baseCamera(const RenderArgs& a) {
    render::OrbitCamera cam;
    cam.yaw = static_cast<float>(a.yawDeg * 3.14159265358979 / 180.0);
    cam.pitch = static_cast<float>(a.pitchDeg * 3.14159265358979 / 180.0);
    return cam;
}

// Fixed framing of the whole range, or (follow) a camera that keeps a
// person-sized box around the characters' centre, smoothed over +-0.25 s.
struct CameraPlan {
    bool follow = false;
    render::OrbitCamera fixed;
    float followDistance = 4.0f;
};

CameraPlan planCamera(const RenderArgs& a, render::MotionStage& stage, int first, int last, float aspect) {
    CameraPlan plan;
    render::Bounds all = boundsOver(stage, first, last);
    // Joints lie inside the body: pad by the capsule radii and the head above the top joint.
    all.add(all.min - glm::vec3(0.25f));
    all.add(all.max + glm::vec3(0.25f));
    plan.fixed = baseCamera(a);
    plan.fixed.frame(all, aspect);
    const glm::vec3 ext = all.max - all.min;
    plan.follow = a.camera == "follow" || (a.camera == "auto" && std::max(ext.x, ext.z) > 6.0f);
    if (plan.follow) {
        render::Bounds person;
        person.add(glm::vec3(-1.2f, 0.0f, -1.2f));
        person.add(glm::vec3(1.2f, 2.0f, 1.2f));
        render::OrbitCamera c = baseCamera(a);
        c.frame(person, aspect);
        plan.followDistance = c.distance;
    }
    return plan;
}

render::OrbitCamera cameraAt(const RenderArgs& a, const CameraPlan& plan, render::MotionStage& stage, int offset, int last) {
    if (!plan.follow) return plan.fixed;
    glm::vec3 sum(0.0f);
    int n = 0;
    for (int k = -15; k <= 15; k += 5) {
        stage.poseFrame(std::clamp(offset + k, 0, last));
        sum += stage.bounds().center();
        ++n;
    }
    render::OrbitCamera c = baseCamera(a);
    c.target = sum / static_cast<float>(n);
    c.target.y = 1.0f;
    c.distance = plan.followDistance;
    return c;
}

Status ensureDir(const std::string& dir) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir)) return makeError(dir + ": cannot create the output folder" + (ec ? ": " + ec.message() : ""));
    return {};
}

// The --rig file bound to the skeletons (none without --rig); warnings on
// stderr unless quiet.
Result<SkeletonRigs> loadRigOption(const RenderArgs& a, const std::vector<const Skeleton*>& skeletons) {
    if (a.rig.empty()) return SkeletonRigs{};
    auto rigs = loadRigs(a.rig, skeletons);
    if (rigs && !a.quiet)
        for (const std::string& w : rigs->warnings) std::fprintf(stderr, "fray-cli: warning: %s\n", w.c_str());
    return rigs;
}

// The Vulkan device, its validation messages echoed with --validate.
Result<std::shared_ptr<render::VulkanDevice>> openDevice(const RenderArgs& a) {
    render::DeviceOptions dopt;
    dopt.applicationName = "fray-cli render";
    dopt.validation = a.validate;
    auto device = render::VulkanDevice::create(dopt);
    if (device && a.validate) (*device)->validationLog()->setEcho(true);
    return device;
}

std::string frameFile(const std::string& dir, const char* prefix, int number) {
    char name[64];
    std::snprintf(name, sizeof name, "%s_%06d.png", prefix, number);
    return (fs::path(dir) / name).string();
}

// A planned scene: frames at kSceneFps of scene time, every character posed
// by the scene poser, its path and checkpoints, a flash where a blow lands.
constexpr double kSceneFps = 30.0;

void runScene(const RenderArgs& a, const FrameRange& range, std::pair<int, int> size) {
    if (a.contactSheet) return fail("--contact-sheet: takes motions or a project, not a scene", 2);
    if (const auto mode = postureMode(a.posture); !mode) return fail(mode.error().message, 2);
    const auto postureOpts = postureOptions(a.posture, a.handPins);
    if (!postureOpts) return fail(postureOpts.error().message, 2);
    auto loaded = openScene(a.inputs[0], stderrProgress(a.quiet));
    if (!loaded) return fail(loaded.error().message);
    const int frames = static_cast<int>(std::floor(loaded->scene.duration * kSceneFps)) + 1;
    if (range.first > frames - 1 || (range.last && *range.last > frames - 1))
        return fail("--frames " + a.frames + ": the scene has " + std::to_string(frames) + " frames at 30 per second (0.." +
                        std::to_string(frames - 1) + ")",
                    2);
    const int first = range.first, last = range.last.value_or(frames - 1);
    SceneStage stage(std::move(*loaded));
    if (Status s = stage.setPosture(*postureMode(a.posture), stderrProgress(a.quiet), *postureOpts); !s) return fail(s.error().message);
    if (const auto* report = stage.postureReport()) printPostureNotes(*report, a.quiet);
    const auto rigs = loadRigOption(a, stage.skeletons());
    if (!rigs) return fail(rigs.error().message);
    if (Status s = ensureDir(a.out); !s) return fail(s.error().message);

    const sim::Scene& scene = stage.scene();
    // Fixed framing of the whole range.
    render::Bounds bounds = stage.bounds(first / kSceneFps, last / kSceneFps);
    bounds.add(bounds.min - glm::vec3(0.25f));
    bounds.add(bounds.max + glm::vec3(0.25f));
    // The stage of a scene planned on one stays in view.
    if (const render::Bounds sb = stage.stageBounds(); !sb.empty()) {
        bounds.add(sb.min);
        bounds.add(sb.max);
    }
    const float aspect = static_cast<float>(size.first) / static_cast<float>(size.second);
    render::OrbitCamera camera = baseCamera(a);
    camera.frame(bounds, aspect);
    // A long scene (a football run) is followed: a box around the first
    // character (the main character, the carrier).
    const glm::vec3 extent = bounds.max - bounds.min;
    const bool follow = a.camera == "follow" || (a.camera == "auto" && std::max(extent.x, extent.z) > 30.0f);

    auto device = openDevice(a);
    if (!device) return fail(device.error().message);
    render::RendererOptions ropt;
    ropt.width = size.first;
    ropt.height = size.second;
    ropt.msaaSamples = a.msaa;
    ropt.quality = a.fast ? render::Quality::Fast : render::Quality::High;
    auto renderer = render::Renderer::create(*device, ropt);
    if (!renderer) return fail(renderer.error().message);
    if (Status s = applyRigs(*rigs, **renderer); !s) return fail(s.error().message);

    FrameDescription frame;
    frame.settings.shadows = !a.noShadows;
    frame.settings.grid = !a.noGrid;
    frame.settings.labels = a.labels;
    frame.camera = camera;
    frame.trajectories = stage.trajectories();
    frame.checkpoints = stage.checkpoints();
    frame.floorBitmap = stage.floorBitmap();
    std::vector<render::Flash> flashes;
    render::Image image;
    int written = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (int f = first; f <= last; f += range.step) {
        const double t = f / kSceneFps;
        stage.pose(t, a.labels ? SceneStage::Labels::All : SceneStage::Labels::None);
        frame.characters = stage.shown();
        if (const auto followed = stage.jointPositions(0); follow && !followed.empty()) {
            const glm::vec3 centre(followed[0].x, 1.0f, followed[0].z);
            render::Bounds near;
            near.add(centre - glm::vec3(4.0f, 1.0f, 4.0f));
            near.add(centre + glm::vec3(4.0f, 1.0f, 4.0f));
            frame.camera = baseCamera(a);
            frame.camera.frame(near, aspect);
        }
        flashes.clear();
        for (const auto& h : scene.hits) {
            const double age = t - h.time;
            if (age < 0 || age > 0.25) continue;
            // At the defender's head or chest joint, fading.
            const auto& lib = stage.library();
            const auto& joints = lib.motion(lib.actions()[static_cast<std::size_t>(h.attackAction)].motion).joints;
            const int joint = h.target == sim::kHead ? joints.head : (joints.chest >= 0 ? joints.chest : joints.pelvis);
            const auto pos = stage.jointPositions(h.defender);
            if (joint < 0 || static_cast<std::size_t>(joint) >= pos.size()) continue;
            const glm::vec4 col = h.blocked ? glm::vec4(0.4f, 0.7f, 1.0f, 0.9f) : glm::vec4(1.0f, 0.35f, 0.1f, 0.9f);
            flashes.push_back({pos[static_cast<std::size_t>(joint)], 0.12f + 0.5f * static_cast<float>(age), col * glm::vec4(1, 1, 1, 1.0f - static_cast<float>(age / 0.25) * 0.7f)});
        }
        frame.flashes = flashes;
        if (Status s = (*renderer)->render(frame, &image); !s) return fail(s.error().message);
        if (Status s = render::writePng(frameFile(a.out, "frame", f), image); !s) return fail(s.error().message);
        ++written;
        if (!a.quiet && written % 50 == 0) std::fprintf(stderr, "fray-cli: render %d frames\n", written);
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("wrote %d frames (%dx%d) of %s to %s in %.2f s on %s\n", written, size.first, size.second, a.inputs[0].c_str(),
                a.out.c_str(), secs, (*device)->description().c_str());
    const auto& log = (*device)->validationLog();
    if (a.validate && (log->errors() > 0 || log->warnings() > 0))
        return fail(std::to_string(log->errors()) + " Vulkan validation errors and " + std::to_string(log->warnings()) +
                        " warnings (see above)",
                    3);
}

void run(const RenderArgs& a) {
    auto range = parseFrames(a.frames);
    if (!range) return fail(range.error().message, 2);
    auto size = parseSize(a.size);
    if (!size) return fail(size.error().message, 2);
    if (a.camera != "auto" && a.camera != "fixed" && a.camera != "follow")
        return fail("--camera " + a.camera + ": expected auto, fixed or follow", 2);
    if (a.columns < 0 || a.maxCells < 1) return fail("--columns must be >= 0 and --max-cells >= 1", 2);
    if (a.inputs.size() == 1 && fs::path(a.inputs[0]).extension() == ".frayscene") return runScene(a, *range, *size);
    if (!a.posture.empty()) return fail("--posture: only for a scene (.frayscene); motions and projects are drawn as captured", 2);
    if (a.handPins) return fail("--hand-pins: only for a scene (.frayscene) with --posture physics", 2);
    auto clips = loadClips(a);
    if (!clips) return fail(clips.error().message);

    // Frame range check against the clips before any Vulkan work.
    int longest = 0;
    for (const Clip& c : *clips) longest = std::max(longest, c.last - c.first + 1);
    const bool sheetMid = a.contactSheet && a.frames.empty();
    if (!sheetMid) {
        if (range->first > longest - 1)
            return fail("--frames " + a.frames + ": " + (a.contactSheet ? "the longest cell has " : "the motion has ") +
                            std::to_string(longest) + " frames (0.." + std::to_string(longest - 1) + ")",
                        2);
        if (range->last && *range->last > longest - 1)
            return fail("--frames " + a.frames + ": " + (a.contactSheet ? "the longest cell has " : "the motion has ") +
                            std::to_string(longest) + " frames (0.." + std::to_string(longest - 1) + ")",
                        2);
    }
    const int first = range->first;
    const int last = range->last.value_or(longest - 1);
    std::vector<const Skeleton*> skeletons;
    for (const Clip& c : *clips) skeletons.push_back(&c.motion->skeleton());
    const auto rigs = loadRigOption(a, skeletons);
    if (!rigs) return fail(rigs.error().message);
    if (Status s = ensureDir(a.out); !s) return fail(s.error().message);

    auto device = openDevice(a);
    if (!device) return fail(device.error().message);

    const int columns = a.contactSheet
                            ? (a.columns > 0 ? a.columns : static_cast<int>(std::ceil(std::sqrt(static_cast<double>(clips->size())))))
                            : 1;
    const int rows = a.contactSheet ? (static_cast<int>(clips->size()) + columns - 1) / columns : 1;
    render::RendererOptions ropt;
    ropt.width = size->first;
    ropt.height = size->second;
    ropt.msaaSamples = a.msaa;
    ropt.quality = a.fast ? render::Quality::Fast : render::Quality::High;
    auto renderer = render::Renderer::create(*device, ropt);
    if (!renderer) return fail(renderer.error().message);
    if (Status s = applyRigs(*rigs, **renderer); !s) return fail(s.error().message);
    const float aspect = static_cast<float>(size->first) / static_cast<float>(size->second);

    FrameDescription frame;
    frame.settings.shadows = !a.noShadows;
    frame.settings.grid = !a.noGrid;
    frame.settings.labels = a.labels;
    render::Image image, sheet;
    int written = 0;
    const auto t0 = std::chrono::steady_clock::now();

    if (!a.contactSheet) {
        MotionSource source(*clips, true, a.labels);
        render::MotionStage& stage = source.stage();
        const CameraPlan plan = planCamera(a, stage, first, last, aspect);
        std::vector<std::vector<glm::vec3>> trails;
        std::vector<render::Polyline> lines;
        std::vector<render::Checkpoint> marks;
        if (a.trail) {
            for (std::size_t i = 0; i < clips->size(); ++i) {
                const Clip& c = (*clips)[i];
                const render::StageActor& actor = stage.actors()[i];
                trails.push_back(render::floorTrail(*c.motion, c.first + first, std::min(c.first + last, c.last), 2, actor.offset));
            }
            for (std::size_t i = 0; i < trails.size(); ++i) {
                const glm::vec3 col = clips->size() == 1 ? glm::vec3(1.0f, 0.75f, 0.2f) : render::teamColor(static_cast<int>(i));
                lines.push_back({trails[i], glm::vec4(col, 0.9f), 0.05f});
                if (!trails[i].empty()) {
                    marks.push_back({trails[i].front(), glm::vec4(col, 1.0f), 0.3f, {}});
                    marks.push_back({trails[i].back(), glm::vec4(col, 1.0f), 0.3f, {}});
                }
            }
        }
        frame.trajectories = lines;
        frame.checkpoints = marks;
        for (int f = first; f <= last; f += range->step) {
            frame.camera = cameraAt(a, plan, stage, f, last);
            stage.poseFrame(f);
            frame.characters = stage.instances();
            if (Status s = (*renderer)->render(frame, &image); !s) return fail(s.error().message);
            if (Status s = render::writePng(frameFile(a.out, "frame", clips->front().first + f), image); !s)
                return fail(s.error().message);
            ++written;
            if (!a.quiet && written % 50 == 0) std::fprintf(stderr, "fray-cli: render %d frames\n", written);
        }
    } else {
        // One renderer at cell size; each cell is rendered alone and copied into the sheet.
        std::vector<MotionSource> cells;
        std::vector<CameraPlan> plans;
        for (const Clip& c : *clips) {
            cells.reserve(clips->size());
        cells.emplace_back(std::vector<Clip>{c}, false, false);
            const int len = c.last - c.first;
            plans.push_back(planCamera(a, cells.back().stage(), 0, len, aspect));
        }
        sheet.resize(columns * size->first, rows * size->second);
        std::fill(sheet.rgba.begin(), sheet.rgba.end(), std::uint8_t(40));
        const std::uint8_t white[4] = {255, 255, 255, 255};
        const int captionScale = std::max(1, size->second / 180);
        const int sheetFirst = sheetMid ? 0 : first;
        const int sheetLast = sheetMid ? 0 : last;
        for (int t = sheetFirst; t <= sheetLast; t += range->step) {
            for (std::size_t i = 0; i < cells.size(); ++i) {
                render::MotionStage& stage = cells[i].stage();
                const Clip& c = (*clips)[i];
                const int len = c.last - c.first;
                const int offset = sheetMid ? len / 2 : std::min(t, len);
                frame.camera = cameraAt(a, plans[i], stage, offset, len);
                stage.poseFrame(offset);
                frame.characters = stage.instances();
                if (Status s = (*renderer)->render(frame, &image); !s) return fail(s.error().message);
                const int cx = static_cast<int>(i) % columns * size->first;
                const int cy = static_cast<int>(i) / columns * size->second;
                render::blit(image, sheet, cx, cy);
                const std::string caption = c.name + "  " + std::to_string(c.first + offset);
                render::drawText(sheet, cx + 4 * captionScale, cy + 4 * captionScale, caption, captionScale, white, true);
            }
            if (Status s = render::writePng(frameFile(a.out, "sheet", t), sheet); !s) return fail(s.error().message);
            ++written;
        }
    }

    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto& log = (*device)->validationLog();
    std::printf("wrote %d %s (%dx%d) to %s in %.2f s on %s\n", written, a.contactSheet ? "contact sheets" : "frames",
                a.contactSheet ? sheet.width : size->first, a.contactSheet ? sheet.height : size->second, a.out.c_str(), secs,
                (*device)->description().c_str());
    if (a.validate && (log->errors() > 0 || log->warnings() > 0))
        return fail(std::to_string(log->errors()) + " Vulkan validation errors and " + std::to_string(log->warnings()) +
                        " warnings (see above)",
                    3);
}

}  // namespace

void registerRender(CLI::App& app) {
    auto a = std::make_shared<RenderArgs>();
    auto* cmd = app.add_subcommand("render", "Render motions or a planned scene offscreen to PNG frames (or contact sheets); no display needed");
    cmd->add_option("inputs", a->inputs, "Motion files (BVH, FBX, glTF, ...), one .frayscene, or one .frayproj with --contact-sheet")->required();
    cmd->add_option("--out,-o", a->out, "Output folder (created if missing)")->required();
    cmd->add_option("--frames", a->frames,
                    "A:B:STEP frames from 0, B inclusive or 'end' (default: every frame; contact sheet: each cell's middle frame)");
    cmd->add_option("--size", a->size, "Image (or cell) size WIDTHxHEIGHT")->capture_default_str();
    cmd->add_flag("--contact-sheet", a->contactSheet, "One grid image per frame: a cell per motion file, or per action of a project");
    cmd->add_option("--columns", a->columns, "Contact sheet columns (default: about square)");
    cmd->add_option("--max-cells", a->maxCells, "Contact sheet: at most this many cells")->capture_default_str();
    cmd->add_option("--action", a->action, "Contact sheet of a project: only actions with this name, annotation or proposal (marked 'WORD?')");
    cmd->add_option("--yaw", a->yawDeg, "Camera heading in degrees (0: looking along -Z)")
        ->capture_default_str()
        ->check(finiteRange(-3600, 3600));
    cmd->add_option("--pitch", a->pitchDeg, "Camera elevation in degrees")->capture_default_str()->check(finiteRange(-90, 90));
    cmd->add_option("--camera", a->camera, "fixed (frame the whole range), follow, or auto (follow when the path exceeds 6 m; a scene: the first character, when the scene spans over 30 m)")
        ->capture_default_str();
    cmd->add_flag("--trail", a->trail, "Draw each character's floor path over the range, with start and end markers");
    cmd->add_flag("--labels", a->labels, "Label characters with their take (or the current action of a project)");
    cmd->add_flag("--no-shadows", a->noShadows, "Disable the shadow map");
    cmd->add_flag("--no-grid", a->noGrid, "Plain floor");
    cmd->add_option("--msaa", a->msaa, "Multisampling (1, 2, 4, 8; clamped to the device; default 4, or 1 with --fast)")
        ->check(CLI::IsMember({1, 2, 4, 8}));
    cmd->add_flag("--fast", a->fast, "Viewport quality: no MSAA, blob shadows instead of the shadow map, lower-poly bodies");
    cmd->add_flag("--validate", a->validate, "Vulkan validation layers on; any message fails the run (exit 3)");
    cmd->add_flag("--quiet", a->quiet, "No progress (or rig warnings) on stderr");
    cmd->add_option("--rig", a->rig,
                    "Draw the characters as this skinned rig (glTF/GLB, FBX, ...) instead of capsules; its bones are matched "
                    "to the motion's joints by name (e.g. a GLB from 'fray-cli export')");
    addPostureFlag(cmd, a->posture,
                   "A scene's posture mode: kinematic (the captured clips; default) or physics (the posture solver, "
                   "docs/POSTURE.md)");
    addHandPinsFlag(cmd, a->handPins);
    addImportFlags(cmd, a->flags);
    cmd->callback([a] { run(*a); });
}

}  // namespace fray::cli
