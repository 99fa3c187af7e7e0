// Reads the measure JSON of every sweep run (DIR/NAME.json, NAME = source__target; DIR/NAME.rc
// holds the run's exit status) and prints the table of mesh measures beside each target's own
// clip. Judged: torn limbs (seam drift p99 within 1.5x the own clip's, or 5% of the height) and
// the floor (lowest vertex within 3% of the height in the median frame, 10% at p95, counted from
// where the source is: a jump is in the air on both sides) and stretch (edges' stretch p99
// within 3x the own clip's, or 300%: a body pulled into a bar along its spine read ok on torn
// seams and floor alone). A node tree with no skin (its meshes
// hung rigidly on a few nodes, "rigid" in the JSON) is judged on the floor of its joints, bone tips
// and those meshes only: a rigid part cannot tear or stretch. Pairs in
// REQUIRED must pass unless listed in SHORT (with why); every run must succeed and no figure
// may be NaN. Exit 1 on a failure.
// usage: node sweep.mjs DIR
import { readdirSync, readFileSync } from 'node:fs';

const REQUIRED = [
  'cmu_01_01__RobotExpressive', 'cmu_01_01__Wizard', 'cmu_01_01__girl', 'cmu_01_01__RiggedFigure',
  'cmu_01_01__BCN_Epileptic', 'cmu_01_01__ninja', 'cmu_01_01__vrm_sample', 'cmu_01_01__Fox',
  'cmu_01_01__Testwuson', 'cmu_01_01__draconis_fire_dragon', 'bandai_walk__Wizard',
  'Fox-Walk__animala_horse', 'Fox-Walk__animalia_wolf', 'Fox-Walk__animalia_cat',
  'Fox-Walk__Testwuson',
  // The Fox standing still onto bodies of other builds: they floated 3-19% of their height while
  // the mesh placement's lift, pose and all, was taken for the skeleton's floor.
  'Fox-Survey__RiggedFigure', 'Fox-Survey__BCN_Epileptic', 'Fox-Survey__ninja',
  'Fox-Survey__Testwuson', 'Fox-Survey__animala_horse',
];
// Still short, and why (doc/retargeting.md, "What is still short").
const SHORT = {
};

const dir = process.argv[2];
const pct = (x) => (x === undefined ? '-' : (100 * x).toFixed(1));
const finite = (o) => Object.values(o || {}).every((v) => typeof v !== 'number' || Number.isFinite(v));
let failed = 0;
const rows = [];
for (const f of readdirSync(dir).filter((f) => f.endsWith('.rc')).sort()) {
  const name = f.slice(0, -3);
  const rc = readFileSync(`${dir}/${f}`, 'utf8').trim();
  let j = {};
  try { j = JSON.parse(readFileSync(`${dir}/${name}.json`, 'utf8')); } catch { /* no JSON */ }
  const m = j.mesh, r = j.mesh_reference;
  let verdict = 'run failed';
  if (rc === '0' && !finite(j)) verdict = 'NaN';
  else if (rc === '0' && !m) verdict = 'no skinned mesh';
  else if (rc === '0') {
    const tornLimit = Math.max(r ? 1.5 * r.seam_p99 : 0, 0.05);
    const torn = m.rigid || m.seam_p99 <= tornLimit;
    const floor = Math.abs(m.floor_median) <= 0.03 && m.floor_p95 <= 0.10;
    const stretch = m.rigid || m.stretch_p99 <= Math.max(r ? 3 * r.stretch_p99 : 0, 3.0);
    verdict = torn && floor && stretch ? 'ok'
      : [torn ? '' : 'torn', floor ? '' : 'floor', stretch ? '' : 'stretch'].filter(Boolean).join('+');
    if (m.rigid) verdict += ' (no skin: floor of its skeleton and node meshes)';
  }
  const required = REQUIRED.includes(name);
  if (rc !== '0' || verdict === 'NaN') failed++;
  else if (required && !verdict.startsWith('ok') && !SHORT[name]) failed++;
  if (required && verdict.startsWith('ok') && SHORT[name]) console.log(`note: ${name} passes now; take it off the short list`);
  rows.push(`| ${name.replace('__', ' → ')}${required ? ' *' : ''} | ${m?.rigid ? 'n/a' : m ? `${pct(m.seam_p99)} [${pct(r?.seam_p99)}]` : '-'} | ${m ? `${m.floor_median >= 0 ? '+' : ''}${pct(m.floor_median)} / ${pct(m.floor_p95)} [${r ? pct(r.floor_p95) : '-'}]` : '-'} | ${m ? `${pct(m.parts_below)}%` : '-'} | ${m?.rigid ? 'n/a' : m ? `${pct(m.stretch_p99)} [${pct(r?.stretch_p99)}]` : '-'} | ${verdict}${required && !verdict.startsWith('ok') && SHORT[name] ? ` (short: ${SHORT[name]})` : ''} |`);
}
console.log('| source → target (* required) | torn p99 % [own] | floor median / p95 % [own p95] | parts under floor, frames | stretch p99 % [own] | verdict |');
console.log('|---|---|---|---|---|---|');
for (const r of rows) console.log(r);
console.log(`${rows.length} runs, ${failed} failing`);
process.exit(failed ? 1 : 0);
