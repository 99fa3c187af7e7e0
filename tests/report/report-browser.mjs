// Drives report.html pages in Debian's chromium through playwright-core, as a person would use them,
// and checks what appears on screen (doc/report.md). Usage:
//   node report-browser.mjs ARTEFACT_DIR CASE...   CASE = kind:name:page.html:joints
// kind "full" (mesh, motion, mapping: every check), "names" (hostile joint names, expects the
// name list in RF_REPORT_NAMES as JSON), "large" (many frames or joints: opens, rows, sampling).
// Prints TAP-like lines; exit 0 when every check passed, 1 otherwise, 77 when the browser or
// playwright-core is missing.
import { createRequire } from 'node:module';
import { existsSync, statSync } from 'node:fs';
import { pathToFileURL } from 'node:url';

const npm = process.env.RF_NPM_DIR || '';
const chromiumPath = process.env.RF_CHROMIUM || '/usr/bin/chromium';
let chromium;
try {
  chromium = createRequire(npm + '/')('playwright-core').chromium;
} catch (e) {
  console.log(`# SKIP: playwright-core not found in ${npm} (./quickstart.sh deps installs it): ${e.message}`);
  process.exit(77);
}
if (!existsSync(chromiumPath)) {
  console.log(`# SKIP: no chromium at ${chromiumPath} (apt-get install chromium)`);
  process.exit(77);
}

const [artefacts, ...cases] = process.argv.slice(2);
let failed = 0, n = 0;
function check(ok, what) {
  n++;
  if (!ok) failed++;
  console.log(`${ok ? 'ok' : 'not ok'} ${n} - ${what}`);
  return ok;
}

const BACKGROUND = [0x1e, 0x21, 0x27];
const browser = await chromium.launch({
  executablePath: chromiumPath,
  args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
const context = await browser.newContext({ offline: true, viewport: { width: 1400, height: 1000 } });
const badRequests = [];
await context.route('**/*', (route) => {
  const url = route.request().url();
  if (/^(file|data|blob):/.test(url)) return route.continue();
  badRequests.push(url);
  return route.abort();
});
// Pixels of a PNG, decoded by the browser itself in a page of its own (a WebGL canvas reads blank
// through toDataURL without preserveDrawingBuffer, so pixels come from element screenshots). The
// pixels stay in that page; the measures below run there and return numbers.
const decoder = await context.newPage();
await decoder.setContent('<canvas id="c"></canvas>');
await decoder.evaluate(() => {
  window.imgs = [];
  // luminance variance, share of pixels away from the background, magenta pixels near a point
  window.stats = (id, bg) => {
    const px = window.imgs[id], d = px.data, count = px.width * px.height;
    let sum = 0, sum2 = 0, fg = 0, magenta = 0;
    for (let i = 0; i < count; i++) {
      const r = d[4 * i], g = d[4 * i + 1], b = d[4 * i + 2];
      const y = 0.299 * r + 0.587 * g + 0.114 * b;
      sum += y; sum2 += y * y;
      if (Math.abs(r - bg[0]) + Math.abs(g - bg[1]) + Math.abs(b - bg[2]) > 40) fg++;
      if (r > 200 && g < 70 && b > 200) magenta++;
    }
    const mean = sum / count;
    return { variance: sum2 / count - mean * mean, foreground: fg / count, magenta };
  };
  window.near = (id, p, test) => {
    const px = window.imgs[id], d = px.data;
    let hits = 0;
    for (let y = Math.max(0, Math.round(p.y) - 10); y <= Math.min(px.height - 1, Math.round(p.y) + 10); y++)
      for (let x = Math.max(0, Math.round(p.x) - 10); x <= Math.min(px.width - 1, Math.round(p.x) + 10); x++) {
        const i = 4 * (y * px.width + x);
        if (test(d[i], d[i + 1], d[i + 2])) hits++;
      }
    return hits;
  };
  window.magentaNear = (id, p) => window.near(id, p, (r, g, b) => r > 200 && g < 70 && b > 200);
  window.redNear = (id, p) => window.near(id, p, (r, g, b) => r > 200 && g < 70 && b < 70);
  window.differing = (ia, ib) => {
    const a = window.imgs[ia].data, b = window.imgs[ib].data;
    let n = 0;
    for (let i = 0; i < a.length; i += 4)
      if (Math.abs(a[i] - b[i]) + Math.abs(a[i + 1] - b[i + 1]) + Math.abs(a[i + 2] - b[i + 2]) > 30) n++;
    return n / (a.length / 4);
  };
});
async function pixels(png) {
  return decoder.evaluate(async (b64) => {
    const img = new Image();
    img.src = 'data:image/png;base64,' + b64;
    await img.decode();
    const c = document.getElementById('c');
    c.width = img.width; c.height = img.height;
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    window.imgs.push(g.getImageData(0, 0, img.width, img.height));
    return window.imgs.length - 1;
  }, png.toString('base64'));
}
const stats = (id, bg = BACKGROUND) => decoder.evaluate(([i, b]) => window.stats(i, b), [id, bg]);
const magentaNear = (id, p) => decoder.evaluate(([i, q]) => window.magentaNear(i, q), [id, p]);
const redNear = (id, p) => decoder.evaluate(([i, q]) => window.redNear(i, q), [id, p]);
const differing = (a, b) => decoder.evaluate(([x, y]) => window.differing(x, y), [a, b]);

async function open(file, label) {
  const page = await context.newPage();
  const errors = [];
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('dialog', (d) => { errors.push('a dialog opened: ' + d.message()); d.dismiss(); });
  page.on('crash', () => console.log(`# ${label}: the page crashed`));
  const t0 = Date.now();
  await page.goto(pathToFileURL(file).href);
  await page.waitForSelector('body[data-ready]', { timeout: 30000 });
  await page.waitForTimeout(200); // two frames drawn
  console.log(`# ${label}: ready in ${Date.now() - t0} ms, ${(statSync(file).size / 1e6).toFixed(2)} MB`);
  return { page, errors };
}

async function shot(page, path) {
  const png = await page.locator('#view').screenshot({ path });
  return pixels(png);
}

async function full(name, file, joints) {
  const { page, errors } = await open(file, name);
  const art = (s) => `${artefacts}/${name}-${s}.png`;
  await page.screenshot({ path: art('page'), fullPage: false });
  const first = await shot(page, art('initial'));
  const s0 = await stats(first);
  check(s0.variance > 100 && s0.foreground > 0.01,
    `${name}: the canvas shows something (luminance variance ${s0.variance.toFixed(0)}, ${(100 * s0.foreground).toFixed(1)}% not background)`);
  check(s0.magenta === 0, `${name}: nothing highlighted before a click`);
  const rows = await page.locator('#mapping tbody tr').count();
  check(rows === joints, `${name}: one table row per target joint (${rows} rows, ${joints} joints)`);
  const meshError = await page.evaluate(() => rigflowReport.meshJointError());
  check(meshError >= 0 && meshError < 1e-3, `${name}: the embedded mesh's bones sit on the joints drawn (off by ${meshError} heights)`);

  // a mapped row highlights its target and source joints
  const mapped = page.locator('#mapping tbody tr:not(.unmapped)');
  const rowIndex = await mapped.first().getAttribute('data-target');
  await page.uncheck('#lines'); // the joints alone carry the highlight
  await mapped.first().click();
  await page.waitForTimeout(150);
  const selPx = await shot(page, art('selected'));
  check(await mapped.first().evaluate((r) => r.classList.contains('selected')), `${name}: the clicked row is selected`);
  const where = await page.evaluate(() => rigflowReport.selectedOnScreen());
  const tHits = where.target ? await magentaNear(selPx, where.target) : 0;
  const sHits = where.sources.length && where.sources[0] ? await magentaNear(selPx, where.sources[0]) : 0;
  check(tHits >= 12 && sHits >= 12,
    `${name}: row ${rowIndex} turns its source joint magenta (${sHits} pixels there) and its target joint (${tHits} pixels)`);

  // a click on a target joint selects its row
  const pick = await page.evaluate(() => {
    const n = rigflowReport.targetJoints;
    for (let j = n - 1; j >= 0; j--) {
      const p = rigflowReport.screenOf('target', j);
      if (p && rigflowReport.jointAt(p.x, p.y) === j) return { j, ...p };
    }
    return null;
  });
  if (check(pick !== null, `${name}: a target joint is on screen`)) {
    const box = await page.locator('#view').boundingBox();
    await page.mouse.click(box.x + pick.x, box.y + pick.y);
    await page.waitForTimeout(100);
    const selectedRow = await page.locator('#mapping tbody tr.selected').getAttribute('data-target');
    const hit = await page.evaluate((p) => rigflowReport.jointAt(p.x, p.y), pick);
    check(selectedRow !== null && Number(selectedRow) === hit,
      `${name}: clicking target joint ${hit} on the canvas selects its row (row ${selectedRow})`);
  }
  await page.check('#lines');

  // playback advances frames and moves the picture
  const before = await shot(page, art('before-play'));
  await page.click('#play');
  await page.waitForTimeout(1200);
  await page.click('#play');
  const played = Number(await page.locator('#frame').getAttribute('data-frame'));
  const after = await shot(page, art('playing'));
  check(played > 0, `${name}: playback advanced to frame ${played}`);
  const moved = await differing(before, after);
  check(moved > 0.002, `${name}: the picture changed while playing (${(100 * moved).toFixed(2)}% of pixels)`);

  // scrubbing shows the frame asked for, the same picture each time
  const max = Number(await page.locator('#scrub').getAttribute('max'));
  const k = Math.floor(max / 2);
  await page.uncheck('#follow');
  await page.locator('#scrub').fill('0');
  const zero = await shot(page, art('frame0'));
  await page.locator('#scrub').fill(String(k));
  const shown = Number(await page.locator('#frame').getAttribute('data-frame'));
  const step = await page.evaluate(() => rigflowReport.step);
  const a = await shot(page, art('scrubbed'));
  await page.locator('#scrub').fill('0');
  await page.locator('#scrub').fill(String(k));
  const b = await shot(page, art('scrubbed-again'));
  check(shown === k * step, `${name}: scrubbing to position ${k} shows frame ${shown} (expected ${k * step})`);
  const fromZero = await differing(zero, a), again = await differing(a, b);
  check(fromZero > 0.002, `${name}: frame ${shown} looks different from frame 0 (${(100 * fromZero).toFixed(2)}%)`);
  check(again < 0.001, `${name}: frame ${shown} looks the same when scrubbed to again (${(100 * again).toFixed(3)}% differ)`);
  const meshError2 = await page.evaluate(() => rigflowReport.meshJointError());
  check(meshError2 < 1e-3, `${name}: mesh and joints agree at frame ${shown} (off by ${meshError2} heights)`);

  // feet in contact turn red: the first shown frames with a contact (up to 24), around each foot
  // in contact, until one shows red (a foot may be hidden behind the body in one frame: the
  // fire dragon, seen from the front, hides its feet behind its body in most frames)
  const contacts = await page.evaluate(() => {
    const out = [];
    for (let k = 0; k < rigflowReport.shown && out.length < 24; k++) {
      const on = rigflowReport.contactsAt(k);
      if (on.length) out.push({ k, on });
    }
    return out;
  });
  if (check(contacts.length > 0, `${name}: the measures mark contacts`)) {
    let red = 0, joint = contacts[0].on[0], at_k = contacts[0].k;
    for (const c of contacts) {
      await page.locator('#scrub').fill(String(c.k));
      const picture = await shot(page, art('contact'));
      for (const j of c.on) {
        const at = await page.evaluate((j) => rigflowReport.screenOf('target', j), j);
        const r = at ? await redNear(picture, at) : 0;
        if (r > red) red = r, joint = j, at_k = c.k;
      }
      if (red >= 24) break; // clearly red: no need to look further
    }
    check(red >= 12, `${name}: target joint ${joint}, in contact at position ${at_k}, drawn red (${red} pixels)`);
  }

  // worst frame one click away
  const worst = page.locator('.plot button').first();
  if (check(await worst.count() > 0, `${name}: measure plots offer their worst frame`)) {
    const label = await worst.textContent();
    await worst.click();
    const at = Number(await page.locator('#frame').getAttribute('data-frame'));
    const want = Number(/frame (\d+)/.exec(label)[1]);
    check(Math.abs(at - want) <= step, `${name}: '${label}' jumps to frame ${at}`);
  }
  check(errors.length === 0, `${name}: no console or page errors${errors.length ? ': ' + errors.join(' | ') : ''}`);
  await page.close();
}

async function names(name, file, joints) {
  const { page, errors } = await open(file, name);
  const expected = JSON.parse(process.env.RF_REPORT_NAMES || '[]');
  const cells = await page.locator('#mapping tbody tr td:nth-child(2)').allTextContents();
  const sources = await page.evaluate(() => Array.from(document.querySelectorAll('#mapping tbody td:nth-child(4)')).map((td) => td.textContent));
  check(cells.length === joints, `${name}: one row per joint (${cells.length})`);
  for (const want of expected)
    check(cells.includes(want) || sources.some((s) => s.includes(want)), `${name}: the joint name ${JSON.stringify(want)} shows as text`);
  const injected = await page.evaluate(() => document.querySelectorAll('img, iframe, b, svg, object').length);
  check(injected === 0, `${name}: no element made from a joint name (${injected} found)`);
  const scripts = await page.evaluate(() => document.scripts.length);
  check(scripts === 5, `${name}: the page's own 5 scripts only (${scripts})`);
  check(await page.evaluate(() => window.rfInjected === undefined), `${name}: no injected script ran`);
  check(errors.length === 0, `${name}: no console or page errors${errors.length ? ': ' + errors.join(' | ') : ''}`);
  await page.screenshot({ path: `${artefacts}/${name}-page.png` });
  await page.close();
}

async function large(name, file, joints) {
  const { page, errors } = await open(file, name);
  const rows = await page.locator('#mapping tbody tr').count();
  check(rows === joints, `${name}: one row per target joint (${rows})`);
  const shown = await page.evaluate(() => rigflowReport.shown);
  check(shown <= 1500, `${name}: ${shown} frames shown (at most 1500)`);
  // both inputs have more frames than a page shows (10,000; 2,752 at 120 fps): sampled, and said so
  const notice = await page.locator('#notice').textContent();
  const step = await page.evaluate(() => rigflowReport.step);
  check(step > 1 && /sampled/.test(notice), `${name}: one frame in ${step} shown, and the page says so ('${notice.slice(0, 60)}...')`);
  const s = await stats(await shot(page, `${artefacts}/${name}-initial.png`));
  check(s.variance > 50 && s.foreground > 0.005, `${name}: the canvas shows something`);
  check(errors.length === 0, `${name}: no console or page errors${errors.length ? ': ' + errors.join(' | ') : ''}`);
  await page.close();
}

for (const c of cases) {
  const [kind, name, file, joints] = c.split(':');
  try {
    await ({ full, names, large })[kind](name, file, Number(joints));
  } catch (e) {
    check(false, `${name}: ${e.message.split('\n')[0]}`);
  }
}
check(badRequests.length === 0, `no request left the page's file (${badRequests.slice(0, 3).join(', ')})`);
await browser.close();
console.log(`# ${n - failed} of ${n} checks passed`);
process.exit(failed ? 1 : 0);
