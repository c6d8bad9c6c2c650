# Imports files exported by `fray-cli export` into Blender, one empty scene
# each, and checks every character against the export's scene summary
# (NAME.FORMAT.scene.json, found next to the file by its "files" list):
# - the import succeeds and brings one armature per character of the file
#   (glTF, GLB, FBX: every character; BVH: the file's one character);
# - the file's frame rate (FBX, BVH: Blender takes it) is the export's, and each
#   action lasts the export's key range;
# - each armature's animation covers the whole key range, and its root bone
#   follows the summary's "root_path" (the root joint's scene position at every
#   second and at the last frame) within 1 cm, matched one to one;
# - each armature moves: a static animation (no bone's pose changes over the
#   range) fails.
# Prints a line per file and exits 1 if any check fails.
# Not part of the build (Blender is not a build dependency); the ctest
# export_gltf_validator runs it on the demo duel where `blender` is on PATH:
#   blender -b --factory-startup --python scripts/blender-import-check.py -- out/duel.gltf out/duel.fbx out/duel_red.bvh
# Written for Debian 12's blender 3.4.1 (docs/EXPORT.md).
import builtins
import glob
import itertools
import json
import os
import sys

import bpy
from mathutils import Vector

# Two shims for Debian 12's Blender 3.4 on Python 3.11 and numpy 1.24 (the
# files are not the problem): its BVH importer opens files with mode 'rU',
# which Python 3.11 refuses, and its glTF importer uses numpy.bool, which numpy
# 1.24 removed (install python3-numpy for the glTF importer).
_open = builtins.open
builtins.open = lambda f, mode="r", *a, **k: _open(f, mode.replace("U", ""), *a, **k)
try:
    import numpy
    numpy.bool = bool
except ImportError:
    pass

IMPORTERS = {
    ".gltf": lambda p: bpy.ops.import_scene.gltf(filepath=p),
    ".glb": lambda p: bpy.ops.import_scene.gltf(filepath=p),
    ".fbx": lambda p: bpy.ops.import_scene.fbx(filepath=p),
    # The BVH importer keeps Blender's 24 fps unless asked to take the file's.
    ".bvh": lambda p: bpy.ops.import_anim.bvh(filepath=p, update_scene_fps=True),
}
TOLERANCE_M = 0.01


def summary_for(path):
    """The export summary listing this file, and the characters the file holds."""
    folder, name = os.path.split(os.path.abspath(path))
    for candidate in sorted(glob.glob(os.path.join(folder, "*.scene.json"))):
        with open(candidate) as f:
            try:
                s = json.load(f)
            except ValueError:
                continue
        if s.get("format") != "fray-export" or name not in s.get("files", []):
            continue
        chars = s["characters"]
        if path.lower().endswith(".bvh"):
            chars = [c for c in chars if name == f"{s['name']}_{c['file_name']}.bvh"]
        return candidate, s, chars
    return None, None, None


def to_blender(p):
    """Scene space (Y up, metres) to Blender's Z-up frame, as the importers convert it."""
    return Vector((p[0], -p[2], p[1]))


def root_bone(armature):
    return next(b for b in armature.pose.bones if b.parent is None)


def frame_range(armature):
    action = armature.animation_data.action if armature.animation_data else None
    return tuple(action.frame_range) if action else None


def sample(armature, summary, path_times):
    """Root positions at the summary's times, and whether any bone's pose changes."""
    scene = bpy.context.scene
    f0, f1 = frame_range(armature)
    last = summary["last_frame_time"]
    frames = [f0 + t / last * (f1 - f0) for t in path_times]
    root = root_bone(armature)
    positions, poses = [], []
    for f in frames:
        scene.frame_set(int(f), subframe=f - int(f))
        positions.append(armature.matrix_world @ root.head)
        poses.append([b.matrix_basis.copy() for b in armature.pose.bones])
    moves = any(any(sum(abs(a - b) for ra, rb in zip(p, poses[0][i]) for a, b in zip(ra, rb)) > 1e-4
                    for i, p in enumerate(pose)) for pose in poses[1:])
    return positions, moves


def check(path):
    problems = []
    bpy.ops.wm.read_factory_settings(use_empty=True)
    ext = path[path.rfind("."):].lower()
    summary_path, summary, chars = summary_for(path)
    if summary is None:
        print(f"{path}: FAILED no export summary (*.scene.json) in its folder lists it")
        return False
    if not chars or any("root_path" not in c for c in chars) or "last_frame_time" not in summary:
        print(f"{path}: FAILED {os.path.basename(summary_path)} (version {summary.get('version')}) has no root_path "
              f"for this file's characters; export again with this version of fray-cli")
        return False
    try:
        IMPORTERS[ext](path)
    except Exception as e:  # Blender reports import errors as RuntimeError
        print(f"{path}: FAILED {str(e).splitlines()[-1] if str(e) else repr(e)}")
        return False
    armatures = [o for o in bpy.data.objects if o.type == "ARMATURE"]
    meshes = [o for o in bpy.data.objects if o.type == "MESH"]
    skinned = sum(any(m.type == "ARMATURE" for m in o.modifiers) for o in meshes)
    line = (f"{path}: {len(armatures)} armatures ({', '.join(str(len(a.data.bones)) for a in armatures)} bones), "
            f"{len(meshes)} meshes ({skinned} skinned), {len(bpy.data.actions)} actions")
    if len(armatures) != len(chars):
        problems.append(f"{len(armatures)} armatures for {len(chars)} characters in {os.path.basename(summary_path)}")
    unanimated = [a.name for a in armatures if frame_range(a) is None]
    if unanimated:
        problems.append(f"armature(s) without an action: {', '.join(unanimated)}")
    if problems:
        print(f"{line}; FAILED {'; '.join(problems)}")
        return False

    # Every armature against every character's root path, then the best one-to-one match.
    times = [p[0] for p in chars[0]["root_path"]]  # one timeline for all characters
    sampled = [sample(a, summary, times) for a in armatures]
    def error(ai, ci):
        want = [to_blender(p[1:]) for p in chars[ci]["root_path"]]
        return max((g - w).length for g, w in zip(sampled[ai][0], want))
    best = min(itertools.permutations(range(len(chars))),
               key=lambda perm: sum(error(ai, ci) for ai, ci in enumerate(perm)))
    # Frame rates: FBX and BVH declare theirs (Blender takes it); every
    # action must last the export's key range in seconds at Blender's rate.
    render = bpy.context.scene.render
    fps = render.fps / render.fps_base
    details = [f"scene {fps:g} fps"]
    if ext in (".fbx", ".bvh") and abs(fps - summary["fps"]) > 0.01 * summary["fps"]:
        problems.append(f"the file declares {fps:g} fps; the export was at {summary['fps']:g} fps")
    for ai, ci in enumerate(best):
        a, c = armatures[ai], chars[ci]
        err = error(ai, ci)
        f0, f1 = frame_range(a)
        details.append(f"{c['name']}: {a.name} frames {f0:g}-{f1:g}, root within {err * 100:.2f} cm over "
                       f"{len(times)} times to {times[-1]:g} s")
        seconds = (f1 - f0) / fps
        if abs(seconds - summary["last_frame_time"]) > 1.0 / summary["fps"] + 1e-6:
            problems.append(f"{c['name']}: the action lasts {seconds:g} s at {fps:g} fps, the keys "
                            f"{summary['last_frame_time']:g} s")
        if err > TOLERANCE_M:
            problems.append(f"{c['name']}: the root is {err * 100:.1f} cm from the summary's path")
        if not sampled[ai][1]:
            problems.append(f"{c['name']}: static animation (no bone moves over the key range)")
    print(f"{line}; " + "; ".join(details) + (f"; FAILED {'; '.join(problems)}" if problems else "; ok"))
    return not problems


files = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
if not files:
    print("usage: blender -b --factory-startup --python scripts/blender-import-check.py -- FILE...")
    sys.exit(2)
ok = all([check(p) for p in files])
sys.exit(0 if ok else 1)
