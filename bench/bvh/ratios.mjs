// Ratios of libbvh's BVH import to the peers', from one bench/bvh/run.sh run.
// usage: node ratios.mjs RESULTS_DIR
//   ours_run*.txt, three_run*.txt: RESULT {json} lines (metric "parse"); medians across runs
//   ours_big.txt: the 100k-frame file (memory); assimp.txt: the table run_assimp.sh prints
import { readFileSync, readdirSync } from 'node:fs';
import { basename, join } from 'node:path';

const dir = process.argv[2];
const median = (a) => { const b = [...a].sort((x, y) => x - y); const m = b.length >> 1; return b.length % 2 ? b[m] : 0.5 * (b[m - 1] + b[m]); };
const results = (prefix) => {
  const by = new Map();
  for (const f of readdirSync(dir).filter((n) => n.startsWith(prefix))) {
    for (const l of readFileSync(join(dir, f), 'utf8').split('\n')) {
      if (!l.startsWith('RESULT ')) continue;
      const o = JSON.parse(l.slice(7));
      if (o.metric !== 'parse') continue;
      const k = basename(o.file);
      if (!by.has(k)) by.set(k, []);
      by.get(k).push(o);
    }
  }
  const med = new Map();
  for (const [k, arr] of by) {
    const m = {};
    for (const key of Object.keys(arr[0])) if (typeof arr[0][key] === 'number') m[key] = median(arr.map((o) => o[key]));
    m.runs = arr.length;
    med.set(k, m);
  }
  return med;
};

const ours = results('ours_run'), three = results('three_run'), big = results('ours_big');
const assimp = new Map();
try {
  for (const l of readFileSync(join(dir, 'assimp.txt'), 'utf8').split('\n')) {
    const t = l.trim().split(/\s+/);
    if (t.length === 6 && t[0].endsWith('.bvh')) assimp.set(t[0], { MBps: +t[5], s: +t[3] });
  }
} catch { /* no Assimp figures */ }

const perProcess = new Map(); // ours timed per process like Assimp: file MB seconds
try {
  for (const l of readFileSync(join(dir, 'ours_process.txt'), 'utf8').split('\n')) {
    const t = l.trim().split(/\s+/);
    if (t.length === 3) perProcess.set(t[0], { MBps: +t[1] / +t[2], s: +t[2] });
  }
} catch { /* not measured */ }

const f = (x, d = 1) => (x === undefined || !isFinite(x) ? '-' : x.toFixed(d));
const rows = [];
console.log('\nBVH import, MB/s (median of runs) and ratios; peak RSS added by one import / decoded bytes');
console.log('file'.padEnd(24), 'MB'.padStart(7), 'libbvh'.padStart(8), 'frames/s'.padStart(10), 'three'.padStart(7),
  'x three'.padStart(8), 'assimp'.padStart(7), 'x assimp'.padStart(9), 'RSS/decoded'.padStart(12));
for (const [k, o] of ours) {
  const t = three.get(k), a = assimp.get(k);
  const rt = t ? o.MBps / t.MBps : undefined, ra = a ? o.MBps / a.MBps : undefined;
  rows.push({ file: k, ours: o.MBps, three: t?.MBps, assimp: a?.MBps, x_three: rt, x_assimp: ra, rss_ratio: o.rss_ratio });
  const mb = o.ms * o.MBps / 1e3;
  console.log(k.padEnd(24), f(mb, 3).padStart(7), f(o.MBps).padStart(8), f(o.fps, 0).padStart(10), f(t?.MBps).padStart(7),
    f(rt).padStart(8), f(a?.MBps).padStart(7), f(ra).padStart(9), f(o.rss_ratio, 2).padStart(12));
}
for (const [k, o] of big)
  console.log(`${k}: ${f(o.MBps)} MB/s, ${f(o.fps, 0)} frames/s, peak RSS +${f(o.peak_MB, 1)} MB for ${f(o.decoded_MB, 1)} MB decoded (${f(o.rss_ratio, 2)}x)`);
const xt = rows.map((r) => r.x_three).filter((x) => x !== undefined), xa = rows.map((r) => r.x_assimp).filter((x) => x !== undefined);
if (xt.length) console.log(`three.js: ${f(Math.min(...xt))}x to ${f(Math.max(...xt))}x (goal 20x)`);
if (xa.length) console.log(`Assimp (its CLI wall time, process start included): ${f(Math.min(...xa))}x to ${f(Math.max(...xa))}x (goal 10x)`);
const xp = [];
for (const [k, p] of perProcess) {
  const a = assimp.get(k);
  if (!a) continue;
  xp.push(p.MBps / a.MBps);
  const r = rows.find((x) => x.file === k);
  if (r) Object.assign(r, { ours_process: p.MBps, x_assimp_process: p.MBps / a.MBps });
  console.log(`${k}: one import per process, wall clock: libbvh ${f(p.s * 1e3, 1)} ms = ${f(p.MBps)} MB/s, Assimp ${f(a.s * 1e3, 1)} ms = ${f(a.MBps)} MB/s: ${f(p.MBps / a.MBps)}x`);
}
if (xp.length) console.log(`Assimp, process against process: ${f(Math.min(...xp))}x to ${f(Math.max(...xp))}x (goal 10x)`);
for (const r of rows) console.log('RESULT ' + JSON.stringify({ metric: 'bvh_ratio', ...r }));
