// three.js SkeletonUtils.retargetClip on one of our pairs, for bench/retarget: the source BVH
// through three's BVHLoader, the target rebuilt as three Bones from `bench_retarget export`, the
// joint names mapped as the export says and the hip given; the clip three makes is written out
// frame by frame (local rotations and positions of every target joint, our joint order) for
// `bench_retarget measure` to measure with the same code as our own clip.
// usage: node three_retarget.mjs SOURCE.bvh TARGET.json OUT.bin   (three found on NODE_PATH)
import { existsSync, readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { pathToFileURL } from 'node:url';

// three is installed in a scratch folder (run.sh): found through NODE_PATH, loaded as ES modules
// (its examples import 'three' and resolve to the same build/three.module.js).
const roots = (process.env.NODE_PATH || '').split(':').filter(Boolean);
const root = roots.find((r) => existsSync(join(r, 'three', 'package.json')));
if (!root) throw new Error('three not found on NODE_PATH');
const url = (rel) => pathToFileURL(join(root, 'three', rel)).href;
const THREE = await import(url('build/three.module.js'));
const { BVHLoader } = await import(url('examples/jsm/loaders/BVHLoader.js'));
const SkeletonUtils = await import(url('examples/jsm/utils/SkeletonUtils.js'));

const [srcPath, tgtPath, outPath] = process.argv.slice(2);
console.warn = () => {}; // PropertyBinding warnings
const { skeleton, clip } = new BVHLoader().parse(readFileSync(srcPath, 'utf8'));
const spec = JSON.parse(readFileSync(tgtPath, 'utf8'));

// The target: our joints as three Bones, rest transforms as given.
const bones = spec.joints.map((j) => {
  const b = new THREE.Bone();
  b.name = j.name;
  b.position.fromArray(j.t);
  b.quaternion.fromArray(j.r);
  b.scale.fromArray(j.s);
  return b;
});
const target = new THREE.Object3D();
spec.joints.forEach((j, i) => (j.parent >= 0 ? bones[j.parent] : target).add(bones[i]));
target.updateMatrixWorld(true);
target.skeleton = new THREE.Skeleton(bones);
const names = {};
for (const j of spec.joints) if (j.source) names[j.name] = j.source;

// Writes the clip three made, sampled at its frames: one value per frame in every track.
function write(out, path) {
  const frames = Math.max(...out.tracks.map((t) => t.times.length));
  const duration = out.tracks[0].times[frames - 1];
  const data = new Float32Array(frames * bones.length * 7);
  bones.forEach((b, j) => {
    const q = out.tracks.find((t) => t.name === `.bones[${b.name}].quaternion`);
    const p = out.tracks.find((t) => t.name === `.bones[${b.name}].position`);
    for (let f = 0; f < frames; f++) {
      const o = (f * bones.length + j) * 7;
      // A joint without a track (unmapped, or not the hip) plays its rest.
      data.set(q ? q.values.subarray(f * 4, f * 4 + 4) : spec.joints[j].r, o);
      data.set(p ? p.values.subarray(f * 3, f * 3 + 3) : spec.joints[j].t, o + 4);
    }
  });
  const head = Buffer.alloc(20); // "RFT1", frames, joints (uint32), fps (double), little-endian
  head.write('RFT1', 0, 'ascii');
  head.writeUInt32LE(frames, 4);
  head.writeUInt32LE(bones.length, 8);
  head.writeDoubleLE(frames > 1 ? (frames - 1) / duration : 1, 12);
  writeFileSync(path, Buffer.concat([head, Buffer.from(data.buffer)]));
  console.log(`three.js retargetClip: ${frames} frames x ${bones.length} joints -> ${path}`);
}

// Its defaults, as the peers' bench runs it; then with the hip motion scaled by our leg ratio.
write(SkeletonUtils.retargetClip(target, skeleton, clip, { names, hip: spec.hip }), outPath);
write(SkeletonUtils.retargetClip(target, skeleton, clip, { names, hip: spec.hip, scale: spec.scale }),
  `${outPath}.scaled`);
