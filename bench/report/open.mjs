// Time for report.html pages to open in chromium: navigation to ready (data parsed, the GLB
// loaded, the first frame drawn), each page opened REPS times in a fresh tab; prints the median.
// usage: node open.mjs REPS PAGE.html...   (RF_NPM_DIR: where playwright-core is installed)
import { createRequire } from 'node:module';
import { statSync } from 'node:fs';
import { pathToFileURL } from 'node:url';
const { chromium } = createRequire((process.env.RF_NPM_DIR || '.') + '/')('playwright-core');
const [reps, ...pages] = process.argv.slice(2);
const browser = await chromium.launch({
  executablePath: process.env.RF_CHROMIUM || '/usr/bin/chromium',
  args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
});
const context = await browser.newContext({ offline: true, viewport: { width: 1400, height: 1000 } });
console.log('| page | MB | frames shown | joints (target) | open, median of ' + reps + ' (ms) | of the 3 s goal |');
console.log('|---|---|---|---|---|---|');
for (const file of pages) {
  const times = [];
  let info = null;
  for (let i = 0; i < Number(reps); i++) {
    const page = await context.newPage();
    const t0 = Date.now();
    await page.goto(pathToFileURL(file).href);
    await page.waitForSelector('body[data-ready]', { timeout: 60000 });
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => r())));
    times.push(Date.now() - t0);
    info = await page.evaluate(() => ({ shown: rigflowReport.shown, joints: rigflowReport.targetJoints }));
    await page.close();
  }
  times.sort((a, b) => a - b);
  const med = times[Math.floor(times.length / 2)];
  const name = file.split('/').pop();
  console.log(`| ${name} | ${(statSync(file).size / 1e6).toFixed(2)} | ${info.shown} | ${info.joints} | ${med} | ${(med / 3000).toFixed(2)} |`);
}
await browser.close();
