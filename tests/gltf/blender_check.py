# What Blender's own glTF importer makes of rigflow's exports (run by test_blender.sh):
#   blender -b --factory-startup --python blender_check.py -- CHECK FILE [ARGS]... [CHECK FILE ...]
# Checks, each on a fresh empty scene; one line "OK ..." or "FAIL ..." per check:
#   look FILE MATERIALS IMAGES   at least MATERIALS materials, IMAGES images with pixels, and every
#                                image used by an Image Texture node of some material
#   armature FILE JOINTS SECONDS one armature of JOINTS bones (no empties) whose action lasts
#                                SECONDS (to half a frame)
#   actions FILE NAME...         the armature gets one action per NAME (each name a substring)
#   plays FILE                   one armature with an action and a mesh it deforms: evaluated at the
#                                action's first frame and four more to its last, the skinned vertices
#                                are finite, some vertex moves by over 1% of the mesh's size and the
#                                mesh deforms (the distance between two vertices changes by over 0.1%
#                                of its size: a clip that only carries the mesh whole does not count;
#                                a rod driven by a walk's spine bends little)
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


def skinned_points(meshes, frame):
    bpy.context.scene.frame_set(frame)
    graph = bpy.context.evaluated_depsgraph_get()
    points = []
    for o in meshes:
        ev = o.evaluated_get(graph)
        m = ev.to_mesh()
        co = np.empty(len(m.vertices) * 3)
        m.vertices.foreach_get('co', co)
        ev.to_mesh_clear()
        w = np.array(o.matrix_world)
        co = co.reshape(-1, 3) @ w[:3, :3].T + w[:3, 3]
        points.append(co)
    return np.concatenate(points) if points else np.zeros((0, 3))


def check_plays(path):
    load(path)
    arms = [o for o in bpy.data.objects if o.type == 'ARMATURE']
    action = arms[0].animation_data.action if len(arms) == 1 and arms[0].animation_data else None
    meshes = [o for o in bpy.data.objects if o.type == 'MESH' and
              any(md.type == 'ARMATURE' and md.object in arms for md in o.modifiers)]
    if not action or not meshes:
        return False, f"{len(arms)} armatures, action {action is not None}, {len(meshes)} skinned meshes"
    first, last = (int(round(f)) for f in action.frame_range)
    a = skinned_points(meshes, first)
    others = [skinned_points(meshes, first + (last - first) * k // 4) for k in range(1, 5)]
    size = float(np.linalg.norm(a.max(axis=0) - a.min(axis=0))) if len(a) else 0.0
    finite = bool(np.isfinite(a).all() and all(np.isfinite(b).all() for b in others))
    bend = max(largest_bend(a, b) for b in others) if finite and len(a) > 1 else 0.0
    move = max(float(np.linalg.norm(b - a, axis=1).max()) for b in others) if finite and len(a) else 0.0
    ok = finite and size > 0 and move > 0.01 * size and bend > 0.001 * size
    size = size or 1.0
    return ok, (f"{len(meshes)} skinned meshes, {len(a)} vertices, frames {first}-{last}, "
                f"largest move {move / size:.3f} and bend {bend / size:.4f} of the size, finite {finite}")


def largest_bend(a, b):
    # Random vertex pairs (fixed seed): how much their distance changes between the two frames.
    rng = np.random.default_rng(1)
    i = rng.integers(0, len(a), 20000)
    j = rng.integers(0, len(a), 20000)
    da = np.linalg.norm(a[i] - a[j], axis=1)
    db = np.linalg.norm(b[i] - b[j], axis=1)
    return float(np.abs(db - da).max())


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
        elif kind == 'plays':
            ok, what = check_plays(path)
            i += 2
        elif kind == 'actions':
            names = []
            i += 2
            while i < len(args) and args[i] not in ('look', 'armature', 'actions', 'plays'):
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
