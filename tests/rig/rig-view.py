#!/usr/bin/env python3
"""rig-view.py DUMP OUT.svg: draws rig-dump's output from the side (Z right, Y up) and the front
(X right, Y up): vertices coloured by their heaviest joint, bones as black lines, joints as dots."""
import sys

joints, verts = [], []
for line in open(sys.argv[1]):
    f = line.split()
    if f[0] == 'J':
        joints.append((int(f[2]), float(f[3]), float(f[4]), float(f[5])))
    elif f[0] == 'V':
        verts.append((float(f[1]), float(f[2]), float(f[3]), int(f[4])))
xs = [v[0] for v in verts]; ys = [v[1] for v in verts]; zs = [v[2] for v in verts]
lo = min(min(xs), min(ys), min(zs)); hi = max(max(xs), max(ys), max(zs))
S = 400 / (hi - lo)
def px(a, b, off):
    return off + (a - lo) * S + 10, 420 - (b - lo) * S
out = ['<svg xmlns="http://www.w3.org/2000/svg" width="860" height="440"><rect width="860" height="440" fill="white"/>']
for view, off in ((('z', 'y'), 0), (('x', 'y'), 430)):
    ia = 'xyz'.index(view[0]); ib = 'xyz'.index(view[1])
    for v in verts[::max(1, len(verts) // 6000)]:
        x, y = px(v[ia], v[ib], off)
        h = (v[3] * 47) % 360
        out.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="1.2" fill="hsl({h},80%,55%)"/>')
    for j in joints:
        if j[0] >= 0:
            p = joints[j[0]]
            x1, y1 = px(j[1 + ia], j[1 + ib], off); x2, y2 = px(p[1 + ia], p[1 + ib], off)
            out.append(f'<line x1="{x1:.1f}" y1="{y1:.1f}" x2="{x2:.1f}" y2="{y2:.1f}" stroke="black" stroke-width="2"/>')
        x, y = px(j[1 + ia], j[1 + ib], off)
        out.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="3" fill="black"/>')
out.append('</svg>')
open(sys.argv[2], 'w').write('\n'.join(out))
