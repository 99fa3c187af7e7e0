// The table of a bench/retarget/run.sh run: speed of ours and of three.js retargetClip (medians
// across processes) with their ratio, our distance from the memory bandwidth floor, and the
// quality figures of each tool per pair.
// usage: node ratios.mjs RESULTS_DIR
//   ours_run*.txt, three_run*.txt: RESULT {json} lines (metric "retarget"); membw.txt: membw's
//   output; quality.txt: RESULT lines of bench_retarget measure
import { readFileSync, readdirSync, existsSync } from 'node:fs';
import { basename, join } from 'node:path';

const dir = process.argv[2];
const median = (a) => { const b = [...a].sort((x, y) => x - y); const m = b.length >> 1; return b.length % 2 ? b[m] : 0.5 * (b[m - 1] + b[m]); };
const results = (file) => readFileSync(join(dir, file), 'utf8').split('\n')
  .filter((l) => l.startsWith('RESULT ')).map((l) => JSON.parse(l.slice(7)));

// speed: median joint-frames/s per file and metric across the runs of one tool
const speed = (prefix, metric) => {
  const by = new Map();
  for (const f of readdirSync(dir).filter((n) => n.startsWith(prefix))) {
    for (const o of results(f)) {
      if (o.metric !== metric) continue;
      const k = basename(o.file);
      if (!by.has(k)) by.set(k, []);
      by.get(k).push(o.jfps);
    }
  }
  return new Map([...by].map(([k, v]) => [k, { jfps: median(v), runs: v.length }]));
};
const ours = speed('ours_run', 'retarget'), oursAll = speed('ours_run', 'retarget+setup');
const three = speed('three_run', 'retarget');

// membw: the best single-thread memcpy (read + write) bandwidth
let gbps = NaN;
if (existsSync(join(dir, 'membw.txt'))) {
  const m = readFileSync(join(dir, 'membw.txt'), 'utf8').match(/threads=1 .*?memcpy: ([0-9.]+) GB\/s \(read\+write\)/);
  if (m) gbps = parseFloat(m[1]);
}
const floor = gbps * 1e9 / 32; // joint-frames/s when each moves 32 bytes in and out

const M = (x) => (x / 1e6).toFixed(x >= 1e7 ? 1 : 2);
console.log('\nSpeed (million joint-frames per second, medians; no contact pass)');
console.log('file                     ours    ours+set-up  three.js  ours/three  floor/ours');
for (const [k, o] of ours) {
  const t = three.get(k), a = oursAll.get(k);
  console.log(`${k.padEnd(24)} ${M(o.jfps).padStart(6)}  ${(a ? M(a.jfps) : '-').padStart(11)}  ${(t ? M(t.jfps) : '-').padStart(8)}  ${(t ? (o.jfps / t.jfps).toFixed(0) + 'x' : '-').padStart(10)}  ${(isFinite(floor) ? (floor / o.jfps).toFixed(1) + 'x' : '-').padStart(10)}`);
}
if (isFinite(floor)) console.log(`memory bandwidth floor: ${gbps} GB/s memcpy (read+write, 1 thread) / 32 bytes = ${M(floor)} M joint-frames/s`);

if (existsSync(join(dir, 'quality.txt'))) {
  console.log('\nQuality (CMU 01_01 onto each target; fidelity in degrees, skate in leg lengths per second, ground in leg lengths)');
  console.log('pair                               tool                    fidelity   p95     skate   ground');
  for (const o of results('quality.txt'))
    console.log(`${o.pair.padEnd(34)} ${o.tool.padEnd(22)} ${o.fidelity_mean.toFixed(2).padStart(8)} ${o.fidelity_p95.toFixed(2).padStart(7)} ${o.skate.toFixed(4).padStart(8)} ${o.ground.toFixed(3).padStart(7)}`);
}
for (const [k, o] of ours) {
  const t = three.get(k);
  console.log(`RESULT ${JSON.stringify({ file: k, metric: 'retarget-ratio', ours: o.jfps, three: t ? t.jfps : null, ratio: t ? o.jfps / t.jfps : null, floor, floor_ratio: floor / o.jfps })}`);
}
