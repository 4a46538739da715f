// Drives the playground in headless Chromium (puppeteer-core, installed by
// scripts/install-test-tools.sh, pointed at the system's chromium): opens
// URL, sets each `id=value` on the form as a user would (select or type,
// then a change event), waits for the render's last pass, and writes
// OUT.rgba (the canvas's RGBA bytes), OUT.json (size, command, time, pass
// count, RMSE once the reference is in) and, with SHOT, a screenshot.
// usage: node playground-drive.js PUPPETEER_DIR CHROMIUM URL OUT [SHOT] [id=value...]
const path = require('path');
const fs = require('fs');

const [pptrDir, chromium, url, out, shot, ...sets] = process.argv.slice(2);
const puppeteer = require(path.resolve(pptrDir));

(async () => {
  const browser = await puppeteer.launch({
    executablePath: chromium,
    headless: true,
    args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage'],
  });
  try {
    const page = await browser.newPage();
    await page.setViewport({ width: 1280, height: 900 });
    const logs = [];
    page.on('console', (m) => logs.push(m.text()));
    page.on('pageerror', (e) => logs.push('page error: ' + e.message));
    await page.goto(url, { waitUntil: 'load' });
    // The first render (the form's defaults) starts on load.
    await page.waitForFunction(() => document.getElementById('status').dataset.done !== '0', { timeout: 120000 });
    for (const s of sets) {
      const [id, value] = s.split('=');
      const tag = await page.$eval('#' + id, (el) => el.tagName);
      if (tag === 'SELECT') {
        await page.select('#' + id, value);
      } else {
        await page.$eval('#' + id, (el, v) => {
          el.value = v;
          el.dispatchEvent(new Event('change'));
        }, value);
      }
    }
    // The last change started a new job: wait for its render, then for
    // the reference behind its error plot.
    await page.waitForFunction(() => {
      const st = document.getElementById('status').dataset;
      return st.rendered === '1' || st.done === 'error';
    }, { timeout: 300000 });
    const rendered = await page.evaluate(() => {
      const c = document.getElementById('canvas');
      const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
      return {
        width: c.width, height: c.height, rgba: Array.from(d),
        command: document.getElementById('command').textContent,
        ms: window.playground.lastMs, passes: window.playground.run.complete,
        status: document.getElementById('status').textContent,
        workers: window.playground.workers.length,
      };
    });
    if (rendered.status.startsWith('error')) throw new Error(rendered.status);
    await page.waitForFunction(() => document.getElementById('status').dataset.done !== '0', { timeout: 300000 });
    // Hover over the horizon so the shot shows the magnifier and a pattern.
    const box = await (await page.$('#canvas')).boundingBox();
    await page.mouse.move(box.x + box.width * 0.5, box.y + box.height * 0.345);
    await new Promise((r) => setTimeout(r, 300));
    const rmse = await page.evaluate(() => window.playground.run.rmse.map((p) => [p.pass, p.value]));
    const caption = await page.$eval('#pattern-caption', (el) => el.textContent);
    if (shot && shot !== '-') await page.screenshot({ path: shot, fullPage: true });
    fs.writeFileSync(out + '.rgba', Buffer.from(rendered.rgba));
    delete rendered.rgba;
    fs.writeFileSync(out + '.json', JSON.stringify(Object.assign(rendered, { rmse, caption, logs }), null, 1));
  } finally {
    await browser.close();
  }
})().catch((e) => {
  console.error(e.stack || String(e));
  process.exit(1);
});
