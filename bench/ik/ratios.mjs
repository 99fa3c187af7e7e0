// Ratios of our IK solvers against the peers, from `rigflow ik-bench` CSV files and the peers'
// RESULT lines: node ratios.mjs OURS.csv... -- PEER.txt...
// Medians across files; prints a table per goal and RESULT {json} lines.
import { readFileSync } from 'node:fs';

const args = process.argv.slice(2);
const cut = args.indexOf('--');
const oursFiles = args.slice(0, cut), peerFiles = args.slice(cut + 1);
const median = a => { const b = [...a].sort((x, y) => x - y); const m = b.length >> 1; return b.length % 2 ? b[m] : 0.5 * (b[m - 1] + b[m]); };

const ours = new Map(); // "solver workload" -> [{us, conv, err, it}]
for (const f of oursFiles) {
  const [head, ...rows] = readFileSync(f, 'utf8').trim().split('\n');
  if (head !== 'solver,workload,us_per_solve,converged,mean_error,mean_iterations') throw new Error(`${f}: not ik-bench CSV`);
  for (const r of rows) {
    const [solver, workload, us, conv, err, it] = r.split(',');
    const k = `${solver} ${workload}`;
    if (!ours.has(k)) ours.set(k, []);
    ours.get(k).push({ us: +us, conv: +conv, err: +err, it: +it });
  }
}
const peers = new Map(); // "file metric" -> [RESULT objects]
for (const f of peerFiles) for (const l of readFileSync(f, 'utf8').split('\n')) {
  if (!l.startsWith('RESULT ')) continue;
  const o = JSON.parse(l.slice(7)), k = `${o.file} ${o.metric}`;
  if (!peers.has(k)) peers.set(k, []);
  peers.get(k).push(o);
}
const our = (solver, w, key = 'us') => { const v = ours.get(`${solver} ${w}`); return v ? median(v.map(o => o[key])) : NaN; };
const peer = (file, metric, key = 'us') => { const v = peers.get(`${file} ${metric}`); return v ? median(v.map(o => o[key])) : NaN; };
const f = (x, d = 2) => (Number.isFinite(x) ? x.toFixed(d) : 'n/a');
const verdict = ok => (ok ? 'yes' : 'NO');
const results = [];

console.log('\nCCD and FABRIK against three.js CCDIKSolver (us per solve; goal: >= 20x faster)');
console.log('workload        three_us  three_hit   ccd_us  ccd_hit  ccd_x   fabrik_us  fabrik_hit  fabrik_x  goal');
for (const [n, it] of [[2, 10], [5, 10], [5, 50], [10, 10], [10, 50], [30, 50]]) {
  const w = `chain${n}-it${it}`;
  const t = peer(`chain${n}`, `ccd_it${it}`), th = peer(`chain${n}`, `ccd_it${it}`, 'hit');
  const c = our('ccd', w), fb = our('fabrik', w);
  const cx = t / c, fx = t / fb;
  console.log(`${w.padEnd(15)} ${f(t).padStart(8)} ${f(100 * th, 1).padStart(9)}% ${f(c).padStart(8)} ${f(100 * our('ccd', w, 'conv'), 1).padStart(7)}% ${f(cx, 1).padStart(6)} ${f(fb).padStart(11)} ${f(100 * our('fabrik', w, 'conv'), 1).padStart(10)}% ${f(fx, 1).padStart(9)}  ${verdict(cx >= 20 && fx >= 20)}`);
  results.push({ bench: 'ik', goal: 'ccd-fabrik-vs-three', workload: w, three_us: t, ccd_us: c, fabrik_us: fb, ccd_x: cx, fabrik_x: fx });
}

console.log('\nDLS against closed-chain-ik (us per solve; goal: >= 50x faster)');
console.log('workload        ccik_us  ccik_conv    dls_us  dls_conv   ratio  goal');
for (const [file, w] of [['chain2', 'chain2'], ['chain5', 'chain5'], ['chain10', 'chain10'], ['tree2eff', 'tree2']]) for (const it of [10, 50]) {
  const name = `${w}-it${it}`, t = peer(file, `dls_it${it}`), d = our('dls', name), x = t / d;
  console.log(`${name.padEnd(15)} ${f(t).padStart(8)} ${f(100 * peer(file, `dls_it${it}`, 'conv'), 1).padStart(9)}% ${f(d).padStart(8)} ${f(100 * our('dls', name, 'conv'), 1).padStart(8)}% ${f(x, 1).padStart(7)}  ${verdict(x >= 50)}`);
  results.push({ bench: 'ik', goal: 'dls-vs-closed-chain-ik', workload: name, peer_us: t, dls_us: d, ratio: x });
}

const conv = our('fabrik', 'chain10-it50', 'conv');
console.log(`\nFABRIK on 10-link targets within 50 iterations: ${f(100 * conv, 1)}% converged (goal >= 95%; three's CCD: ${f(100 * peer('chain10', 'ccd_it50', 'hit'), 1)}%)  ${verdict(conv >= 0.95)}`);
results.push({ bench: 'ik', goal: 'fabrik-convergence', workload: 'chain10-it50', converged: conv });
for (const r of results) console.log('RESULT ' + JSON.stringify(r));
