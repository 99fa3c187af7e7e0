#!/usr/bin/env python3
"""Reference values for tests/import/test_import.c, read without rigflow's code.

For .gltf/.glb files the file's own JSON is read: node TRS/matrix composed down the scene tree,
the skins' joint lists and the animation list. For every other format the XML written by
`assimp dump FILE OUT.xml` (Debian's assimp-utils) is read: node matrices composed down the tree,
the animation list. It prints, per file, the clip count and the world (node rest) position of the
joints named on the command line, which test_import.c compares with rest_pose=node.

usage: expected.py FILE JOINT...   (re-run to check a value written into the test)
"""
import json, re, struct, subprocess, sys, tempfile, os


def mat_mul(a, b):
    return [[sum(a[r][k] * b[k][c] for k in range(4)) for c in range(4)] for r in range(4)]


def trs(n):
    if 'matrix' in n:
        m = n['matrix']  # column-major
        return [[m[c * 4 + r] for c in range(4)] for r in range(4)]
    t = n.get('translation', [0, 0, 0]); x, y, z, w = n.get('rotation', [0, 0, 0, 1])
    s = n.get('scale', [1, 1, 1])
    r = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    return [[r[i][0] * s[0], r[i][1] * s[1], r[i][2] * s[2], t[i]] for i in range(3)] + [[0, 0, 0, 1]]


def gltf(path):
    data = open(path, 'rb').read()
    if data[:4] == b'glTF':
        n = struct.unpack('<I', data[12:16])[0]
        doc = json.loads(data[20:20 + n])
    else:
        doc = json.loads(data)
    nodes, world = doc['nodes'], {}

    def walk(i, parent):
        world[i] = mat_mul(parent, trs(nodes[i]))
        for c in nodes[i].get('children', []):
            walk(c, world[i])
    ident = [[float(r == c) for c in range(4)] for r in range(4)]
    for root in doc['scenes'][doc.get('scene', 0)]['nodes']:
        walk(root, ident)
    names = {}
    for i, n in enumerate(nodes):
        names.setdefault(n.get('name', 'nodes[%d]' % i), i)
    skins = [len(s['joints']) for s in doc.get('skins', [])]
    return len(doc.get('animations', [])), skins, {k: world[i] for k, i in names.items() if i in world}


def dump(path):
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, 'dump.xml')
        subprocess.run(['assimp', 'dump', path, out], check=True, capture_output=True)
        text = open(out, encoding='utf-8', errors='replace').read()
    world, stack = {}, []
    tok = re.compile(r'<Node name="([^"]*)">|</Node>|<Matrix4>\s*([-\d.eE+\s]+?)\s*</Matrix4>')
    pending = None
    for m in tok.finditer(text[:text.find('<AnimationList') if '<AnimationList' in text else len(text)]):
        if m.group(1) is not None:
            pending = m.group(1)
        elif m.group(2) is not None and pending is not None:
            v = [float(x) for x in m.group(2).split()]
            local = [v[r * 4:r * 4 + 4] for r in range(4)]
            parent = stack[-1][1] if stack else [[float(r == c) for c in range(4)] for r in range(4)]
            g = mat_mul(parent, local)
            stack.append((pending, g))
            world.setdefault(pending, g)
            pending = None
        elif m.group(0) == '</Node>':
            stack.pop()
    anims = re.search(r'<AnimationList num="(\d+)"', text)
    return int(anims.group(1)) if anims else 0, None, world


def main():
    path, joints = sys.argv[1], sys.argv[2:]
    clips, skins, world = gltf(path) if path.lower().endswith(('.gltf', '.glb')) else dump(path)
    print('%s: clips %d%s' % (path, clips, '' if skins is None else ', skin joints %s' % skins))
    for j in joints:
        m = world[j]
        print('  {"%s", %.6g, %.6g, %.6g},' % (j, m[0][3], m[1][3], m[2][3]))


if __name__ == '__main__':
    main()
