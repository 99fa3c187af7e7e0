// Test skeletons for the report tests, as BVH on stdout:
//   make-bvh.mjs tail TOTAL   a biped (22 joints) with a tail chain making TOTAL joints
//   make-bvh.mjs names        the same biped with joint names full of markup and control characters
//   make-bvh.mjs names-json   those names as a JSON list
const biped = [ // name, parent, offset (Y up, facing +Z, T-pose)
  ['Hips', -1, [0, 10, 0]], ['Spine', 0, [0, 1.5, 0]], ['Chest', 1, [0, 1.5, 0]],
  ['Chest2', 2, [0, 1.5, 0]], ['Neck', 3, [0, 1.2, 0]], ['Head', 4, [0, 1, 0]],
  ['LUpLeg', 0, [1, -0.5, 0]], ['LLeg', 6, [0, -4.5, 0]], ['LFoot', 7, [0, -4.5, 0]], ['LToe', 8, [0, -0.5, 1.5]],
  ['RUpLeg', 0, [-1, -0.5, 0]], ['RLeg', 10, [0, -4.5, 0]], ['RFoot', 11, [0, -4.5, 0]], ['RToe', 12, [0, -0.5, 1.5]],
  ['LShoulder', 3, [0.7, 0.8, 0]], ['LArm', 14, [1.2, 0, 0]], ['LForeArm', 15, [3, 0, 0]], ['LHand', 16, [2.8, 0, 0]],
  ['RShoulder', 3, [-0.7, 0.8, 0]], ['RArm', 18, [-1.2, 0, 0]], ['RForeArm', 19, [-3, 0, 0]], ['RHand', 20, [-2.8, 0, 0]],
];
const hostile = [
  '<img/src=x/onerror=window.rfInjected=1>', '</script><script>window.rfInjected=1</script>',
  'a&amp;b"c\'d\\e', 'bell\x07tab\x09esc\x1b[31mred', '<b>bold</b>\u2028line', 'caf\u00e9\u{1F40D}',
];

function skeleton(kind, arg) {
  const joints = biped.map((j) => [...j]);
  if (kind === 'tail') {
    for (let i = joints.length, p = 0; i < Number(arg); i++) {
      joints.push([`Tail${i}`, p, p === 0 ? [0, -0.2, -1] : [0, 0, -0.4]]);
      p = i;
    }
  } else {
    hostile.forEach((name, i) => { joints[[1, 5, 9, 13, 17, 21][i]][0] = name; });
  }
  return joints;
}

function bvh(joints) {
  const kids = joints.map(() => []);
  joints.forEach((j, i) => { if (j[1] >= 0) kids[j[1]].push(i); });
  const lines = ['HIERARCHY'];
  const write = (i, depth) => { // iterative enough for a 200-joint chain: recursion depth 200 is fine in node
    const pad = '  '.repeat(depth);
    const [name, parent, off] = joints[i];
    lines.push(`${pad}${parent < 0 ? 'ROOT' : 'JOINT'} ${name}`, `${pad}{`, `${pad}  OFFSET ${off.join(' ')}`,
      parent < 0 ? `${pad}  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation`
        : `${pad}  CHANNELS 3 Zrotation Xrotation Yrotation`);
    if (kids[i].length) kids[i].forEach((k) => write(k, depth + 1));
    else lines.push(`${pad}  End Site`, `${pad}  {`, `${pad}    OFFSET 0 0.5 0`, `${pad}  }`);
    lines.push(`${pad}}`);
  };
  write(0, 0);
  const channels = 3 * joints.length + 3;
  const frame = Array(channels).fill(0);
  frame[1] = 10;
  lines.push('MOTION', 'Frames: 2', 'Frame Time: 0.0333333', frame.join(' '), frame.join(' '));
  return lines.join('\n') + '\n';
}

const [kind, arg] = process.argv.slice(2);
if (kind === 'names-json') process.stdout.write(JSON.stringify(hostile));
else process.stdout.write(bvh(skeleton(kind, arg)));
