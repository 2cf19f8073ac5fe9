// End-to-end test of the viewer in a real browser (Debian's chromium, driven by playwright-core):
// starts tinyphong-server on a free loopback port, loads the page, and checks that
//  1. frames arrive and are painted, and the painted canvas pixels hash (FNV-1a 64, RGB) to the
//     checksum the server reports for that frame — byte for byte what the server sent;
//  2. changing the method from the page changes the counters and the image; every method of the
//     device's registry can be selected, renders, and is described under the selector;
//  3. the reference comparison arrives (reference frame paired with the device frame, error stats),
//     and kb-adaptive's budget set from the page makes it sample less;
//  4. the page reconnects by itself when the server restarts;
// and what a review found (2026-12-06): refused values, lights' colours and removal, the reference
// switched off.
// Usage: node e2e.mjs <path to tinyphong-server>
import { spawn } from 'node:child_process';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { chromium } from 'playwright-core';

const serverBin = process.argv[2];
if (!serverBin) throw new Error('usage: node e2e.mjs <tinyphong-server>');
const log = (...a) => console.log('[e2e]', ...a);
let failures = 0;
function check(ok, what) {
  log(ok ? 'PASS' : 'FAIL', what);
  if (!ok) failures++;
}

function startServer(port) {
  return new Promise((resolve, reject) => {
    const args = ['--port', String(port), '--scene', 'teapot', '--width', '320', '--height', '240', '--max-fps', '30'];
    const proc = spawn(serverBin, args, { stdio: ['ignore', 'pipe', 'inherit'] });
    let out = '';
    const timer = setTimeout(() => reject(new Error('server did not start in 30 s: ' + out)), 30000);
    proc.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/serving (http:\/\/127\.0\.0\.1:(\d+)\/)/);
      if (m) { clearTimeout(timer); resolve({ proc, url: m[1], port: Number(m[2]) }); }
    });
    proc.on('exit', (code) => reject(new Error('server exited early: ' + code + ' ' + out)));
  });
}

function stopServer(s) {
  return new Promise((resolve) => {
    if (s.proc.exitCode !== null) return resolve(s.proc.exitCode);
    const t = setTimeout(() => { s.proc.kill('SIGKILL'); }, 5000);
    s.proc.removeAllListeners('exit');
    s.proc.on('exit', (code) => { clearTimeout(t); resolve(code); });
    s.proc.kill('SIGTERM');
  });
}

// Waits until the page's frame is settled: the painted frame is the last one the server reports.
async function settled(page, minId = 0) {
  await page.waitForFunction((min) => {
    const t = window.tp;
    return t.painted && t.stats && t.painted.id >= min && t.stats.frame.id === t.painted.id;
  }, minId, { timeout: 60000, polling: 100 });
  return page.evaluate(() => ({ painted: window.tp.painted, stats: window.tp.stats, state: window.tp.state }));
}

const userDir = mkdtempSync(path.join(tmpdir(), 'tp-chromium-'));
let server = await startServer(0);
let context;
try {
  context = await chromium.launchPersistentContext(userDir, {
    executablePath: '/usr/bin/chromium',
    headless: true,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
           '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  const page = context.pages()[0] ?? (await context.newPage());
  page.on('console', (m) => { if (m.type() === 'error') log('console error:', m.text()); });
  page.on('pageerror', (e) => { log('page error:', e.message); failures++; });
  await page.goto(server.url);

  // 1. Frames arrive and are painted.
  await page.waitForFunction(() => window.tp.framesPainted >= 3, null, { timeout: 60000 });
  check(true, 'frames arrive and are painted');
  // Stop the animation from the page, so that one frame stays and can be compared.
  await page.uncheck('#animate');
  await page.waitForFunction(() => window.tp.state && window.tp.state.animate === false, null, { timeout: 10000 });
  const a = await settled(page);
  check(a.painted.checksum === a.stats.frame.checksum,
        `painted pixels of frame ${a.painted.id} hash to the server's checksum (${a.painted.checksum} vs ${a.stats.frame.checksum})`);
  check(a.painted.sent === a.stats.frame.checksum, 'the frame header carried the same checksum');
  check(a.painted.width === 320 && a.painted.height === 240, 'native size 320x240');
  const pixelsWritten = a.stats.counters.pixels_written ?? 0;
  check(pixelsWritten > 1000, `the device shaded the teapot (pixels_written ${pixelsWritten})`);
  const own = a.painted.counters.pixels_written ?? 0;
  check(own > 1000 && own === pixelsWritten,
        `the frame header carried the frame's own counters (pixels_written ${own})`);
  const shown = await page.evaluate(() => [...document.querySelectorAll('#counters tbody tr')]
      .find((r) => r.cells[0].textContent === 'pixels_written')?.cells[1].textContent);
  check(shown === String(own), `the page shows the painted frame's counters (${shown})`);

  // 2. Change the method from the page: the counters and the image change.
  const methods = a.state.methods;
  const other = methods.find((m) => m !== a.state.method && m === 'flat') ?? methods.find((m) => m !== a.state.method);
  log('methods', methods.join(','), '— switching', a.state.method, '->', other);
  await page.selectOption('#method', other);
  await page.waitForFunction((m) => window.tp.state.method === m, other, { timeout: 10000 });
  const b = await settled(page, a.painted.id + 1);
  check(b.painted.checksum === b.stats.frame.checksum, `after the switch, painted frame ${b.painted.id} matches the server's checksum`);
  check(b.painted.checksum !== a.painted.checksum, 'the image changed');
  check(JSON.stringify(b.stats.counters) !== JSON.stringify(a.stats.counters), 'the counters changed');
  check(JSON.stringify(b.painted.counters) !== JSON.stringify(a.painted.counters), "the painted frame's counters changed");

  // 2b. Every registered method, in turn: selected from the page, rendered (the painted frame is
  // the server's), and described under the selector by its registry row. The server does not
  // re-send a frame identical to the last one (a verification variant renders its method's
  // image), so the page returns to `other` between two methods: each switch shows a new frame.
  const info = b.state.method_info ?? [];
  check(info.length === methods.length && info.every((m, i) => m.name === methods[i] && m.description && m.capabilities),
        `the state describes every method (${info.length} of ${methods.length})`);
  const select = async (name, after) => {
    await page.selectOption('#method', name);
    await page.waitForFunction((n) => window.tp.state.method === n, name, { timeout: 10000 });
    return settled(page, after.painted.id + 1);
  };
  const described = async (m) => {
    const about = await page.textContent('#method-about');
    return [about, about.includes(m.description) && about.includes(m.capabilities)];
  };
  let last = b;
  for (const m of info) {
    if (m.name === other) {
      const [about, ok] = await described(m);
      check(ok, `method ${m.name}: described as "${about}"`);
      continue;
    }
    const f = await select(m.name, last);
    const [about, ok] = await described(m);
    check(f.painted.checksum === f.stats.frame.checksum && f.painted.checksum !== b.painted.checksum &&
          (f.painted.counters.pixels_written ?? 0) > 1000 && ok,
          `method ${m.name}: frame ${f.painted.id} painted as sent, described as "${about}"`);
    last = await select(other, f);
    check(last.painted.checksum === b.painted.checksum, `back on ${other}: the same image as before`);
  }
  const back = last;

  // 3. Reference comparison: a reference frame paired with the device frame, and error stats.
  await page.check('#reference');
  await page.waitForFunction(() => window.tp.refsPainted >= 1 && window.tp.stats.error, null, { timeout: 60000 });
  const e = await page.evaluate(() => window.tp.stats.error);
  check(e.frame_id === back.painted.id && e.correctness > 0.5 && e.correctness <= 1,
        `reference comparison for frame ${e.frame_id}: colour correctness ${e.correctness.toFixed(5)}`);
  const heatPainted = await page.evaluate(() => document.getElementById('heat').width === 320);
  check(heatPainted, 'the difference image is painted');

  // 3b. kb-adaptive's error budget from the page: a larger budget takes fewer exact samples.
  await page.selectOption('#method', 'kb-adaptive');
  await page.waitForFunction(() => window.tp.state.method === 'kb-adaptive', null, { timeout: 10000 });
  const k1 = await settled(page, back.painted.id + 1);
  check(k1.state.budget === 1, `the budget starts at 1 level (${k1.state.budget})`);
  await page.fill('#budget', '8');
  await page.dispatchEvent('#budget', 'change');
  await page.waitForFunction(() => window.tp.state.budget === 8, null, { timeout: 10000 });
  const k8 = await settled(page, k1.painted.id + 1);
  check(k8.painted.checksum === k8.stats.frame.checksum, `at budget 8, painted frame ${k8.painted.id} matches the server's checksum`);
  const samples = (f) => f.painted.counters.lattice_samples ?? 0;
  check(samples(k1) > 0 && samples(k8) < samples(k1),
        `budget 8 samples less than budget 1 (lattice_samples ${samples(k8)} < ${samples(k1)})`);

  // 3c. The specular-only view (ka = kd = 0 for device and reference): a darker frame, painted as
  // sent, its reference comparison for the same frame; the material's ka and kd are kept.
  await page.check('#specular_only');
  await page.waitForFunction(() => window.tp.state.specular_only === true, null, { timeout: 10000 });
  const sp = await settled(page, k8.painted.id + 1);
  check(sp.painted.checksum === sp.stats.frame.checksum && sp.painted.checksum !== k8.painted.checksum &&
        sp.state.ka > 0 && sp.state.kd > 0,
        `specular only: frame ${sp.painted.id} painted as sent, ka ${sp.state.ka} and kd ${sp.state.kd} kept`);
  const brightness = (id) => page.evaluate((cid) => {
    const c = document.getElementById(cid);
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let sum = 0;
    for (let i = 0; i < d.length; i += 4) sum += d[i] + d[i + 1] + d[i + 2];
    return sum;
  }, id);
  await page.waitForFunction((id) => window.tp.stats.error && window.tp.stats.error.frame_id >= id,
                             sp.painted.id, { timeout: 60000 });
  const spe = await page.evaluate(() => window.tp.stats.error);
  check(spe.correctness > 0.5 && spe.correctness <= 1,
        `specular only: reference comparison for frame ${spe.frame_id}, colour correctness ${spe.correctness.toFixed(5)}`);
  const dark = await brightness('device');
  await page.uncheck('#specular_only');
  await page.waitForFunction(() => window.tp.state.specular_only === false, null, { timeout: 10000 });
  const full = await settled(page, sp.painted.id + 1);
  const light = await brightness('device');
  check(full.painted.checksum === full.stats.frame.checksum && dark < light,
        `specular only is darker than the full frame (${dark} < ${light})`);

  // 3d. Compare all methods: the server renders this frame with every registered method; the page
  // shows one point per method with the server's numbers, and a click on a point selects it.
  await page.click('#compare-all');
  await page.waitForFunction(() => window.tp.comparison, null, { timeout: 180000 });
  const cmp = await page.evaluate(() => window.tp.comparison);
  const names = full.state.methods;
  check(cmp.rows.length === names.length && cmp.rows.every((r, i) => r.method === names[i] && !r.error),
        `compare all methods: ${cmp.rows.length} rows, one per registered method, none refused`);
  const gouraudRow = cmp.rows.find((r) => r.method === 'gouraud');
  check(gouraudRow && gouraudRow.time_ratio === 1 && cmp.rows.every((r) => r.correctness > 0.5 && r.correctness <= 1),
        'the times are ratios to Gouraud, the colour correctness of every method in (0.5, 1]');
  const pts = await page.evaluate(() => [...document.querySelectorAll('#chart .pt')].map((g) =>
    ({ method: g.dataset.method, c: Number(g.dataset.correctness), t: Number(g.dataset.time) })));
  const byName = new Map(cmp.rows.map((r) => [r.method, r]));
  check(pts.length === names.length && new Set(pts.map((p) => p.method)).size === names.length &&
        pts.every((p) => byName.has(p.method) && byName.get(p.method).correctness === p.c &&
                         byName.get(p.method).time_ratio === p.t),
        `the chart has one point per registered method (${pts.length}) at the server's numbers`);
  const shot = await page.locator('#chart').screenshot();
  check(shot.length > 4000, `the chart's screenshot is not empty (${shot.length} bytes of PNG)`);
  const pickMethod = names.includes('quadratic') ? 'quadratic' : names[names.length - 1];
  await page.dispatchEvent(`#chart .pt[data-method="${pickMethod}"] circle`, 'click');
  await page.waitForFunction((m) => window.tp.state.method === m, pickMethod, { timeout: 10000 });
  check(true, `a click on ${pickMethod}'s point selected it`);

  // 3e. Side by side: at 640x480 in a 1600-pixel-wide window the device, reference and difference
  // views stand in one row ("fit" zoom), none overlapping, all inside the window.
  await page.setViewportSize({ width: 1600, height: 900 });
  await page.fill('#width', '640');
  await page.fill('#height', '480');
  await page.click('#apply-size');
  await page.waitForFunction(() => window.tp.state.width === 640 && document.getElementById('heat').width === 640 &&
                             document.getElementById('device').width === 640, null, { timeout: 60000 });
  const boxes = await page.evaluate(() => ['device', 'ref', 'heat'].map((id) => {
    const r = document.getElementById(id).getBoundingClientRect();
    return { top: r.top, left: r.left, right: r.right, width: r.width };
  }));
  const row = boxes.every((b) => Math.abs(b.top - boxes[0].top) < 1) &&
      boxes[0].right <= boxes[1].left && boxes[1].right <= boxes[2].left && boxes[2].right <= 1600 &&
      boxes.every((b) => b.width > 300);
  check(row, `side by side at 640x480 in 1600 px: ${boxes.map((b) => `${Math.round(b.left)}-${Math.round(b.right)}@${Math.round(b.top)}`).join(', ')}`);

  // 3f. Found by review (2026-12-06). A refused value gives way to the server's in its control
  // (the server sends no state for a refused message).
  const budgetNow = await page.evaluate(() => window.tp.state.budget);
  await page.fill('#budget', '20');
  await page.dispatchEvent('#budget', 'change');
  await page.waitForFunction(() => window.tp.replies.some((r) => r.type === 'error' && r.request === 'set_budget'),
                             null, { timeout: 10000 });
  const budgetShown = await page.inputValue('#budget');
  check(budgetShown === String(budgetNow), `a refused budget (20) gives way to the server's (${budgetShown})`);

  // Without the material's own (a, b) the fields show the pair the device derives from n, so that
  // choosing (a, b) starts from what renders (they were blank, or 0, which is refused).
  const ab = await page.evaluate(() => [window.tp.state.use_ab, window.tp.state.a, window.tp.state.b,
    document.getElementById('a').value, document.getElementById('b').value]);
  check(ab[0] === false && ab[1] > 0 && ab[1] < ab[2] && Number(ab[3]) === Number(ab[1].toPrecision(4)) &&
        Number(ab[4]) === Number(ab[2].toPrecision(4)),
        `without use_ab the a and b fields show the device's (a, b) for n (${ab[3]}, ${ab[4]})`);
  // The smallest (a, b) a scene file may hold, (1e-6, 2e-6), set from the page, is shown as it is
  // and can be applied again from the fields (they showed 0.0000, and "set exponent" sent a = 0,
  // which the server refused; found by review, 2026-12-08). Then back to n.
  await page.check('#use-ab');
  await page.fill('#a', '0.000001');
  await page.fill('#b', '0.000002');
  await page.click('#apply-exp');
  await page.waitForFunction(() => window.tp.state.use_ab && window.tp.state.a === 1e-6 &&
                             window.tp.state.b === 2e-6, null, { timeout: 10000 });
  await page.click('#n'); // the focus off the fields, so that the state's values fill them
  await page.evaluate(() => { window.tp.replies.length = 0; });
  await page.click('#apply-exp');
  await page.waitForFunction(() => window.tp.replies.some((r) => r.request === 'set_exponent'), null,
                             { timeout: 10000 });
  const again = await page.evaluate(() => [document.getElementById('a').value,
    document.getElementById('b').value, window.tp.replies.filter((r) => r.type === 'error' &&
      r.request === 'set_exponent').length, window.tp.state.a]);
  check(Number(again[0]) === 1e-6 && Number(again[1]) === 2e-6 && again[2] === 0 && again[3] === 1e-6,
        `(a, b) = (1e-6, 2e-6) shows as (${again[0]}, ${again[1]}) and applies again unrefused`);
  // With n = 1 the device's pair has b = 1.73, above π/2, the server's bound: the field holds it at
  // 1.570796, so (a, b) from the fields is taken, not refused (found by review, 2026-12-08). Then
  // back to the scene's n.
  const nBefore = await page.evaluate(() => window.tp.state.n);
  await page.check('#use-n');
  await page.fill('#n', '1');
  await page.click('#apply-exp');
  await page.waitForFunction(() => !window.tp.state.use_ab && window.tp.state.n === 1, null,
                             { timeout: 10000 });
  await page.click('#ka'); // the focus off the exponent's fields
  await page.check('#use-ab');
  await page.evaluate(() => { window.tp.replies.length = 0; });
  await page.click('#apply-exp');
  // The reply can come before the state that shows the change (the next frame's): wait for the
  // state, or for a refusal, so that a late state cannot flip the n / (a, b) choice below.
  await page.waitForFunction(() => window.tp.replies.some((r) => r.type === 'error') ||
                             (window.tp.state.use_ab && window.tp.state.b === 1.570796), null,
                             { timeout: 10000 });
  const top = await page.evaluate(() => [document.getElementById('b').value,
    window.tp.replies.filter((r) => r.type === 'error').map((r) => r.error), window.tp.state.use_ab,
    window.tp.state.b]);
  check(Number(top[0]) === 1.570796 && top[1].length === 0 && top[2] && top[3] === 1.570796,
        `n = 1's b shows as ${top[0]} and (a, b) from the fields applies unrefused (${JSON.stringify(top)})`);
  await page.check('#use-n');
  await page.fill('#n', String(nBefore));
  await page.click('#apply-exp');
  await page.waitForFunction((n) => !window.tp.state.use_ab && window.tp.state.n === n, nBefore,
                             { timeout: 10000 });

  // A light's row keeps a colour above 1 and its exact value: "set" to move the light sends it back
  // unchanged (a colour picker alone holds 8 bits in [0, 1]).
  const nLights = await page.evaluate(() => window.tp.state.lights.length);
  await page.click('#add-light');
  await page.waitForFunction((n) => window.tp.state.lights.length === n + 1 &&
                             document.querySelectorAll('#lights .light').length === n + 1, nLights, { timeout: 10000 });
  await page.evaluate((i) => window.tp.send({ type: 'set_light', index: i, color: [3, 2.5, 0.3] }), nLights);
  const lightRow = () => page.locator('#lights .light').nth(nLights);
  await page.waitForFunction((i) => {
    const r = document.querySelectorAll('#lights .light')[i];
    return window.tp.state.lights[i].color[0] === 3 && r && r.querySelector('.intensity').value === '3';
  }, nLights, { timeout: 10000 });
  await lightRow().locator('input').nth(0).fill('0.5');
  await lightRow().locator('button', { hasText: 'set' }).click();
  await page.waitForFunction((i) => window.tp.state.lights[i].vector[0] === 0.5, nLights, { timeout: 10000 });
  const moved = await page.evaluate((i) => window.tp.state.lights[i].color, nLights);
  check(JSON.stringify(moved) === JSON.stringify([3, 2.5, 0.3]),
        `moving a light from its row keeps its colour (${JSON.stringify(moved)})`);
  // "remove" from the row: the list follows at once (the clicked button keeps the focus).
  await lightRow().locator('button', { hasText: 'remove' }).click();
  await page.waitForFunction((n) => window.tp.state.lights.length === n &&
                             document.querySelectorAll('#lights .light').length === n, nLights, { timeout: 10000 });
  check(true, `after "remove" the list shows ${nLights} light(s), as the server has`);

  // The reference switched off: its view and the difference go blank, and a client that joins
  // afterwards gets no reference frame (the server kept the last one and sent it).
  await page.uncheck('#reference');
  await page.waitForFunction(() => window.tp.state.reference === false, null, { timeout: 10000 });
  const blank = await page.evaluate(() => ['ref', 'heat'].every((id) => {
    const c = document.getElementById(id);
    return c.getContext('2d').getImageData(0, 0, c.width, c.height).data.every((v) => v === 0);
  }) && document.getElementById('ref-id').textContent === '');
  check(blank, 'with the reference off, the reference and difference views are blank');
  const late = await context.newPage();
  await late.goto(server.url);
  await late.waitForFunction(() => window.tp.framesPainted >= 1 && window.tp.state, null, { timeout: 30000 });
  await late.waitForTimeout(1500);
  const lateRefs = await late.evaluate(() => window.tp.refsPainted);
  check(lateRefs === 0, `a client joining with the reference off paints no reference (${lateRefs})`);
  await late.close();

  // 4. Restart the server on the same port: the page reconnects and paints again.
  const port = server.port;
  const before = await page.evaluate(() => window.tp.framesPainted);
  await stopServer(server);
  await page.waitForFunction(() => !window.tp.connected, null, { timeout: 10000 });
  server = await startServer(port);
  await page.waitForFunction((n) => window.tp.connected && window.tp.framesPainted > n, before, { timeout: 30000 });
  check(true, 'reconnected after a server restart');
} catch (err) {
  log('FAIL', err.stack || err);
  failures++;
} finally {
  if (context) await context.close();
  const code = await stopServer(server);
  check(code === 0, `server exited cleanly on SIGTERM (code ${code})`);
  rmSync(userDir, { recursive: true, force: true });
}
log(failures ? `${failures} failure(s)` : 'all passed');
process.exit(failures ? 1 : 0);
