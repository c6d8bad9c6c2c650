# Imports exported files into Blender, one empty scene each, and prints what
# came in (armatures, bones, skinned meshes, actions, the root bone's position
# at frames 1 and 31). Exits 1 if an import fails or brings no armature.
# Not part of CI (Blender is not a build dependency); run by hand:
#   blender -b --factory-startup --python scripts/blender-import-check.py -- out/duel.gltf out/duel.fbx out/duel_red.bvh
# Checked with Debian 12's blender 3.4.1 (docs/EXPORT.md).
import builtins
import sys

import bpy

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
    ".bvh": lambda p: bpy.ops.import_anim.bvh(filepath=p),
}


def check(path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    ext = path[path.rfind("."):].lower()
    try:
        IMPORTERS[ext](path)
    except Exception as e:  # Blender reports import errors as RuntimeError
        print(f"{path}: FAILED {str(e).splitlines()[-1] if str(e) else repr(e)}")
        return False
    armatures = [o for o in bpy.data.objects if o.type == "ARMATURE"]
    meshes = [o for o in bpy.data.objects if o.type == "MESH"]
    skinned = sum(any(m.type == "ARMATURE" for m in o.modifiers) for o in meshes)
    ranges = [tuple(int(x) for x in a.frame_range) for a in bpy.data.actions]
    line = (f"{path}: {len(armatures)} armatures ({', '.join(str(len(a.data.bones)) for a in armatures)} bones), "
            f"{len(meshes)} meshes ({skinned} skinned), {len(ranges)} actions, frames {sorted(set(ranges))}")
    if armatures:
        a, scene = armatures[0], bpy.context.scene
        heads = []
        for f in (1, 31):
            scene.frame_set(f)
            heads.append(tuple(round(v, 3) for v in (a.matrix_world @ a.pose.bones[0].head)))
        line += f"; {a.pose.bones[0].name} at frames 1, 31: {heads[0]}, {heads[1]}"
    print(line)
    return bool(armatures)


ok = all([check(p) for p in sys.argv[sys.argv.index("--") + 1:]])
sys.exit(0 if ok else 1)
