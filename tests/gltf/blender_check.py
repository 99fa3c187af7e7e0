# What Blender's own glTF importer makes of rigflow's exports (run by test_blender.sh):
#   blender -b --factory-startup --python blender_check.py -- CHECK FILE [ARGS]... [CHECK FILE ...]
# Checks, each on a fresh empty scene; one line "OK ..." or "FAIL ..." per check:
#   look FILE MATERIALS IMAGES   at least MATERIALS materials, IMAGES images with pixels, and every
#                                image used by an Image Texture node of some material
#   armature FILE JOINTS SECONDS one armature of JOINTS bones (no empties) whose action lasts
#                                SECONDS (to half a frame)
#   actions FILE NAME...         the armature gets one action per NAME (each name a substring)
import sys

import bpy
import numpy as np

if not hasattr(np, "bool"):
    np.bool = bool  # Debian's Blender 3.4 glTF add-on still says np.bool, gone since numpy 1.24


def fresh():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def load(path):
    fresh()
    bpy.ops.import_scene.gltf(filepath=path)


def check_look(path, materials, images):
    load(path)
    mats = [m for m in bpy.data.materials if m.users]
    imgs = [i for i in bpy.data.images if i.size[0] > 0 and i.size[1] > 0]
    used = set()
    for m in mats:
        if m.node_tree:
            for n in m.node_tree.nodes:
                if n.type == 'TEX_IMAGE' and n.image:
                    used.add(n.image.name)
    ok = len(mats) >= materials and len(imgs) >= images and all(i.name in used for i in imgs)
    return ok, f"{len(mats)} materials, {len(imgs)} images with pixels, {len(used)} used by textures"


def check_armature(path, joints, seconds):
    load(path)
    arms = [o for o in bpy.data.objects if o.type == 'ARMATURE']
    empties = [o for o in bpy.data.objects if o.type == 'EMPTY']
    bones = len(arms[0].data.bones) if arms else 0
    action = arms[0].animation_data.action if arms and arms[0].animation_data else None
    fps = bpy.context.scene.render.fps / bpy.context.scene.render.fps_base
    length = (action.frame_range[1] - action.frame_range[0]) / fps if action else -1
    ok = len(arms) == 1 and bones == joints and not empties and abs(length - seconds) <= 0.5 / fps
    return ok, (f"{len(arms)} armatures, {bones} bones, {len(empties)} empties, "
                f"action of {length:.3f} s at {fps:g} fps")


def check_actions(path, names):
    load(path)
    actions = [a.name for a in bpy.data.actions]
    found = [n for n in names if any(n in a for a in actions)]
    ok = len(actions) == len(names) and len(found) == len(names)
    return ok, f"actions {actions}"


def main(args):
    failed = 0
    i = 0
    while i < len(args):
        kind, path = args[i], args[i + 1]
        if kind == 'look':
            ok, what = check_look(path, int(args[i + 2]), int(args[i + 3]))
            i += 4
        elif kind == 'armature':
            ok, what = check_armature(path, int(args[i + 2]), float(args[i + 3]))
            i += 4
        elif kind == 'actions':
            names = []
            i += 2
            while i < len(args) and args[i] not in ('look', 'armature', 'actions'):
                names.append(args[i])
                i += 1
            ok, what = check_actions(path, names)
        else:
            print(f"FAIL unknown check {kind}")
            return 1
        print(f"{'OK' if ok else 'FAIL'} {kind} {path}: {what}", flush=True)
        failed += not ok
    return 1 if failed else 0


code = main(sys.argv[sys.argv.index('--') + 1:] if '--' in sys.argv else [])
sys.stdout.flush()
if code:
    sys.exit(code)
