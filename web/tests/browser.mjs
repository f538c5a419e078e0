// The web page (web/dist, built by web/build.sh) in headless Chromium on its WebGPU adapter
// (SwiftShader, on the CPU), driven by playwright-core and served by a static server on
// 127.0.0.1 that this script starts and stops. Checks, against independent truth:
//   - ?demo=grid40&figure=640x480 and ?demo=grid:10&figure=640x480: #status says 64000 glyphs
//     after the first frame, and each figure matches `tensorglyph render --demo … --size
//     640x480` on lavapipe (>= 99 % of pixels within 3/255);
//   - ?demo=grid:10&effects=outlines,shadows,ao&figure=640x480: the figure effects on WebGPU
//     against `render … --outlines --shadows --shadow-map 1024 --ao` (the same bound);
//   - picking: the eigenvalues the page shows for the glyph under the pointer are those of the
//     tensor it shows (a Jacobi eigensolver here);
//   - ?url= a DIPY fit (tests/data/dti/dipy_small101) opens with DIPY's voxel count;
//   - a file chosen while the viewer is still loading waits (#status says so) and then opens;
//   - the file input: a truncated file gets the one-line error naming it, and good files then
//     still open: a detached NRRD and an FSL eigen set from their files given together, and
//     DIPY's fit;
//   - the underlay input: DIPY's FA map under its fit gives the figure of `tensorglyph render
//     tensors.nii.gz --underlay fa.nii.gz` (>= 99 % of pixels within 3/255);
//   - SH series: MRtrix's CSD fit (.mif) opens as ODF glyphs whose figure is `tensorglyph
//     render`'s (the same bound), the status counts its 64 series, and a hovered glyph's
//     largest peak is sh2peaks' (within 1°);
//   - peaks: MRtrix's sh2peaks image opens as sticks whose figure is `tensorglyph render`'s
//     (the same bound); the status counts its 192 peaks;
//   - BEP016: a map and its JSON sidecar given together open, and a picked glyph's principal
//     direction is numpy's in the frame the sidecar names (tests/data/bids);
//   - without a WebGPU adapter the page names browsers that have one.
// Measured, not asserted: navigation to grid40's first frame and its frame time, and, when
// TENSORGLYPH_WEB_BRAIN names a whole-brain volume (`cargo run --example brain_volume -- FILE`),
// opening it by ?url= (read and decomposed on the page's one thread).
// A screenshot of the page and the figures are kept in the output folder (TENSORGLYPH_WEB_OUT,
// default target/web-tests). Without Chromium or web/dist the test skips, unless CI is set.
//
// Run: (cd web/tests && npm ci && node browser.mjs), after bash web/build.sh and cargo build.

import { spawnSync } from 'node:child_process';
import fs from 'node:fs';
import http from 'node:http';
import path from 'node:path';
import { fileURLToPath } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const repo = path.resolve(here, '../..');
const dist = path.join(repo, 'web/dist');
const dipy = path.join(repo, 'tests/data/dti/dipy_small101');
const out = path.resolve(process.env.TENSORGLYPH_WEB_OUT || path.join(repo, 'target/web-tests'));
const brain = process.env.TENSORGLYPH_WEB_BRAIN && path.resolve(process.env.TENSORGLYPH_WEB_BRAIN);
const chromiumPath = process.env.CHROMIUM || '/usr/bin/chromium';
const cli = process.env.TENSORGLYPH_CLI || path.join(repo, 'target/debug/tensorglyph');
// Headless Chromium has a WebGPU adapter here only with these: SwiftShader's Vulkan for WebGPU,
// and no Vulkan surface (with one, the GPU process drops the page's WebGPU instance once a
// canvas is configured, and every read-back fails).
const FLAGS = [
  // A CPU rasteriser's long frames (ODF glyphs) are no hang.
  '--disable-gpu-watchdog',
  '--no-sandbox',
  '--enable-unsafe-webgpu',
  '--enable-features=Vulkan',
  '--use-vulkan=swiftshader',
  '--use-webgpu-adapter=swiftshader',
  '--disable-vulkan-surface',
  '--use-angle=swiftshader',
];
const LONG = 180_000;

function skip(why) {
  if (process.env.CI) {
    console.error(`FAIL: ${why} (CI is set, so this is not skipped)`);
    process.exit(1);
  }
  console.log(`skipped: ${why}`);
  process.exit(0);
}

if (!fs.existsSync(chromiumPath)) skip(`no Chromium at ${chromiumPath} (apt-get install chromium)`);
if (!fs.existsSync(path.join(dist, 'index.html'))) skip('no web/dist (run bash web/build.sh)');
if (!fs.existsSync(cli)) skip(`no ${cli} (run cargo build)`);
let chromium;
try {
  ({ chromium } = await import('playwright-core'));
} catch {
  skip('playwright-core is not installed (cd web/tests && npm ci)');
}
fs.mkdirSync(out, { recursive: true });

const failures = [];
function check(ok, what) {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}`);
  if (!ok) failures.push(what);
}

// The page's files at /, the DIPY fit at /data/ and the brain at /brain.nii.gz (what ?url=
// fetches beside the page).
const TYPES = { '.html': 'text/html', '.js': 'text/javascript', '.wasm': 'application/wasm' };
const server = http.createServer((req, res) => {
  const url = new URL(req.url, 'http://127.0.0.1');
  let file = decodeURIComponent(url.pathname);
  let root = file.startsWith('/data/') ? dipy : dist;
  if (file.startsWith('/data/')) file = file.slice('/data'.length);
  if (brain && file === '/brain.nii.gz') [root, file] = [path.dirname(brain), path.basename(brain)];
  if (file.endsWith('/')) file += 'index.html';
  const full = path.join(root, path.normalize(file));
  if (!full.startsWith(root)) {
    res.writeHead(403).end();
    return;
  }
  fs.readFile(full, (err, body) => {
    if (err) {
      res.writeHead(404).end();
      return;
    }
    res.writeHead(200, { 'content-type': TYPES[path.extname(full)] || 'application/octet-stream' });
    res.end(body);
  });
});
await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
const base = `http://127.0.0.1:${server.address().port}/`;

// The native figures: render's defaults, on lavapipe; `args` say what (`--demo grid40`, a file).
function nativeFigure(name, args, size = '640x480') {
  const png = path.join(out, `native_${name}_${size}.png`);
  const r = spawnSync(cli, ['render', ...args, '--size', size, '-o', png], { stdio: 'inherit' });
  check(r.status === 0, `tensorglyph render ${args.map((a) => path.basename(a)).join(' ')} --size ${size} ran`);
  return png;
}

// With a display (xvfb-run in CI) the window is composited, so the page's screenshot shows the
// viewer; headless Chromium leaves the WebGPU canvas blank in screenshots.
const browser = await chromium.launch({
  headless: !process.env.DISPLAY,
  executablePath: chromiumPath,
  args: FLAGS,
});
const text = (page, id) => page.evaluate((id) => document.getElementById(id).textContent, id);
async function open(query, viewport = { width: 1200, height: 800 }) {
  const page = await browser.newPage({ viewport });
  page.on('console', (m) => {
    if (m.type() === 'error' || m.type() === 'warning') console.log(`  console: ${m.text().slice(0, 200)}`);
  });
  page.on('pageerror', (e) => console.log(`  page error: ${e}`));
  const start = Date.now();
  await page.goto(base + query);
  return { page, start };
}
const statusMatching = (page, re) =>
  page.waitForFunction(
    (re) => new RegExp(re).test(document.getElementById('status').textContent),
    re.source,
    { timeout: LONG },
  );


async function figureOf(page) {
  await page.waitForFunction(
    () => (document.getElementById('figure').getAttribute('src') || '').startsWith('data:image/png'),
    null,
    { timeout: LONG },
  );
  return page.getAttribute('#figure', 'src');
}

// Pixels of the page's figure (a data URL) and a native PNG, decoded by the browser: how many
// are within 3/255 in every channel, and how many are not background (glyphs).
async function compare(page, src, nativePng) {
  const nativeUrl = `data:image/png;base64,${fs.readFileSync(nativePng).toString('base64')}`;
  return page.evaluate(
      async ([a, b]) => {
        const pixels = async (url) => {
          const img = new Image();
          img.src = url;
          await img.decode();
          const c = document.createElement('canvas');
          [c.width, c.height] = [img.width, img.height];
          const g = c.getContext('2d');
          g.drawImage(img, 0, 0);
          return { w: img.width, h: img.height, d: g.getImageData(0, 0, img.width, img.height).data };
        };
        const [p, q] = [await pixels(a), await pixels(b)];
        if (p.w !== q.w || p.h !== q.h) return { size: `${p.w}x${p.h} vs ${q.w}x${q.h}` };
        let close = 0;
        let glyph = 0;
        for (let i = 0; i < p.d.length; i += 4) {
          let worst = 0;
          for (let k = 0; k < 4; k++) worst = Math.max(worst, Math.abs(p.d[i + k] - q.d[i + k]));
          if (worst <= 3) close++;
          if (p.d[i] < 200 || p.d[i + 1] < 200 || p.d[i + 2] < 200) glyph++;
        }
        return { n: p.d.length / 4, close, glyph };
      },
      [src, nativeUrl],
    );
}

try {
  // The demo, its first frame, its figure against the native one, and picking.
  {
    const { page, start } = await open('?demo=grid40&figure=640x480');
    await statusMatching(page, /^64000 glyphs · [0-9.]+ ms\/frame · WebGPU: /);
    const firstFrame = Date.now() - start;
    const status = await text(page, 'status');
    check(true, `grid40 shows: "${status}" (${firstFrame} ms from navigation)`);
    const src = await figureOf(page);
    fs.writeFileSync(path.join(out, 'web_grid40_640x480.png'), Buffer.from(src.split(',')[1], 'base64'));
    const cmp = await compare(page, src, nativeFigure('grid40', ['--demo', 'grid40']));
    check(!cmp.size, `the figure is 640x480 (${cmp.size || 'yes'})`);
    check(cmp.glyph > 0.05 * cmp.n, `the figure shows glyphs (${cmp.glyph} of ${cmp.n} pixels)`);
    const frac = cmp.close / cmp.n;
    check(frac >= 0.99, `grid40's figure matches the native render: ${(100 * frac).toFixed(4)} % of pixels within 3/255`);

    // Picking: hover the middle of the view until the page shows a glyph.
    const box = await page.locator('#view').boundingBox();
    let pick = '';
    for (let i = 0; i < 30 && !pick.includes('λ'); i++) {
      await page.mouse.move(box.x + box.width * 0.6 + i, box.y + box.height * 0.5 + (i % 5));
      await page.waitForTimeout(1000);
      pick = await text(page, 'pick');
    }
    check(pick.includes('λ'), `hovering a glyph shows it (${pick.split('\n')[0] || 'nothing'})`);
    if (pick.includes('λ')) {
      const lines = pick.split('\n');
      const t = lines.slice(3, 6).flatMap((l) => l.trim().split(/\s+/).map(Number));
      const shown = lines[6].replace('λ = ', '').split(',').map(Number);
      const want = jacobiEigenvalues(t);
      const ok = shown.every((l, i) => Math.abs(l - want[i]) <= 1e-3 * Math.max(Math.abs(want[0]), 1e-30));
      check(ok, `its eigenvalues [${shown}] are the shown tensor's [${want.map((x) => x.toExponential(4))}]`);
    }
    await page.screenshot({ path: path.join(out, 'page_grid40.png') });
    console.log(`measured: navigation to first frame of grid40 ${firstFrame} ms; ${status}`);
    await page.close();
  }

  // The same with glyphs large enough to have insides.
  {
    const { page } = await open('?demo=grid:10&figure=640x480');
    const src = await figureOf(page);
    fs.writeFileSync(path.join(out, 'web_grid10_640x480.png'), Buffer.from(src.split(',')[1], 'base64'));
    const cmp = await compare(page, src, nativeFigure('grid10', ['--demo', 'grid:10']));
    const frac = cmp.close / cmp.n;
    check(!cmp.size && cmp.glyph > 0.02 * cmp.n, `grid:10's figure is 640x480 with glyphs (${cmp.size || cmp.glyph})`);
    check(frac >= 0.99, `grid:10's figure matches the native render: ${(100 * frac).toFixed(4)} % of pixels within 3/255`);
    await page.close();
  }

  // The figure effects on WebGPU: the composite pass composed with the shape code for its
  // exact shadow rays, and the occlusion volume, against the native figure with the same
  // effects (the viewer's shadow map is Shadows::default's 1024²).
  {
    const { page } = await open('?demo=grid:10&effects=outlines,shadows,ao&figure=640x480');
    const src = await figureOf(page);
    fs.writeFileSync(path.join(out, 'web_grid10_effects_640x480.png'), Buffer.from(src.split(',')[1], 'base64'));
    const cmp = await compare(page, src, nativeFigure('grid10_effects', ['--demo', 'grid:10', '--outlines', '--shadows', '--shadow-map', '1024', '--ao']));
    const frac = cmp.close / cmp.n;
    check(!cmp.size && cmp.glyph > 0.02 * cmp.n, `grid:10's figure with effects is 640x480 with glyphs (${cmp.size || cmp.glyph})`);
    check(frac >= 0.99, `grid:10's figure with outlines, shadows and AO matches the native render: ${(100 * frac).toFixed(4)} % of pixels within 3/255`);
    await page.close();
  }

  // A whole brain by ?url=: how long reading and decomposing take on the page's one thread.
  if (brain) {
    const { page, start } = await open('?url=brain.nii.gz');
    await statusMatching(page, / glyphs · /);
    console.log(`measured: the brain by ?url=, ${Date.now() - start} ms from navigation: ${await text(page, 'status')}`);
    await page.close();
  }

  // ?url=: a real DTI fit, beside the page.
  const voxels = JSON.parse(fs.readFileSync(path.join(dipy, 'expected.json'))).eigenvalues.length;
  {
    const { page } = await open('?url=data/tensors.nii.gz');
    await statusMatching(page, new RegExp(`(^| of )${voxels} glyphs · `));
    check(true, `?url= opens DIPY's fit: "${await text(page, 'status')}"`);
    await page.close();
  }

  // A file chosen while the viewer is still loading (its wasm held back 3 s here, as a slow
  // network would) waits, #status says so, and it opens once the viewer has started.
  {
    const page = await browser.newPage({ viewport: { width: 1200, height: 800 } });
    page.on('pageerror', (e) => console.log(`  page error: ${e}`));
    await page.route('**/*.wasm', async (route) => {
      await new Promise((resolve) => setTimeout(resolve, 3000));
      await route.continue();
    });
    await page.goto(base, { waitUntil: 'domcontentloaded' });
    const early = await page.evaluate(() => document.body.dataset.state ?? '');
    await page.setInputFiles('#file', path.join(dipy, 'tensors.nii.gz'));
    const waitingText = await text(page, 'status');
    check(early !== 'ready' && /tensors\.nii\.gz will open when it is ready/.test(waitingText),
      `a file chosen before the viewer is ready waits: "${waitingText}"`);
    await statusMatching(page, new RegExp(`(^| of )${voxels} glyphs · `));
    check((await text(page, 'error')) === '', `and opens once it is: "${await text(page, 'status')}"`);
    await page.close();
  }

  // The file input: a truncated file, then a good one.
  {
    const { page } = await open('');
    await page.waitForFunction(() => document.body.dataset.state === 'ready', null, { timeout: LONG });
    const good = fs.readFileSync(path.join(dipy, 'tensors.nii.gz'));
    await page.setInputFiles('#file', {
      name: 'cut.nii.gz',
      mimeType: 'application/gzip',
      buffer: good.subarray(0, Math.floor(good.length / 2)),
    });
    await page.waitForFunction(() => document.getElementById('error').textContent !== '', null, { timeout: LONG });
    const error = await text(page, 'error');
    check(error.startsWith('cut.nii.gz') && !error.includes('\n'), `a truncated file: one line naming it ("${error}")`);
    // Then good files, each changing the count so that the status is not the last one's: a
    // .nhdr after its data file (given together), DIPY's fit, the six files of an FSL eigen set
    // (numpy's counts: tests/data/dti/expected.json).
    const dti = path.join(repo, 'tests/data/dti');
    const truth = JSON.parse(fs.readFileSync(path.join(dti, 'expected.json'))).files;
    const steps = [
      [['nrrd_detached.raw', 'nrrd_detached.nhdr'].map((n) => path.join(dti, n)), truth['nrrd_detached.nhdr'].eigenvalues.length],
      [[{ name: 'tensors.nii.gz', mimeType: 'application/gzip', buffer: good }], voxels],
      [['L1', 'L2', 'L3', 'V1', 'V2', 'V3'].map((m) => path.join(dti, `fsl_eigen_oblique_${m}.nii.gz`)),
        truth.fsl_eigen_oblique.eigenvalues.length],
    ];
    for (const [files, n] of steps) {
      await page.setInputFiles('#file', files);
      await statusMatching(page, new RegExp(`(^| of )${n} glyphs · `));
      const names = files.map((f) => f.name || path.basename(f)).join(' + ');
      check((await text(page, 'error')) === '', `${names} open: "${await text(page, 'status')}"`);
    }
    await page.close();
  }

  // The underlay: DIPY's FA map chosen as the underlay, then its fit; the figure is that of
  // `tensorglyph render tensors.nii.gz --underlay fa.nii.gz`.
  {
    const { page } = await open('?figure=640x480');
    await page.waitForFunction(() => document.body.dataset.state === 'ready', null, { timeout: LONG });
    await page.setInputFiles('#underlay', path.join(dipy, 'fa.nii.gz'));
    await page.setInputFiles('#file', path.join(dipy, 'tensors.nii.gz'));
    const src = await figureOf(page);
    fs.writeFileSync(path.join(out, 'web_underlay_640x480.png'), Buffer.from(src.split(',')[1], 'base64'));
    const args = [path.join(dipy, 'tensors.nii.gz'), '--underlay', path.join(dipy, 'fa.nii.gz')];
    const cmp = await compare(page, src, nativeFigure('underlay', args));
    const frac = cmp.close / cmp.n;
    check(!cmp.size && (await text(page, 'error')) === '', `the fit with its FA underlay opens (${cmp.size || 'no error'})`);
    check(frac >= 0.99, `its figure matches the native render: ${(100 * frac).toFixed(4)} % of pixels within 3/255`);
    await page.screenshot({ path: path.join(out, 'page_underlay.png') });
    await page.close();
  }

  // SH series: MRtrix's CSD fit (tests/data/sh, dwi2fod of DIPY's small_64D) opens as ODF
  // glyphs from its .mif, its figure is that of `tensorglyph render FILE`, and a glyph under
  // the pointer shows its voxel's series and its largest peak where MRtrix's sh2peaks finds it
  // (expected.json: every voxel, scanner axes, which are the world's).
  {
    const shDir = path.join(repo, 'tests/data/sh');
    const name = 'mrtrix_lmax8.mif';
    const file = path.join(shDir, name);
    const truth = JSON.parse(fs.readFileSync(path.join(shDir, 'expected.json'))).files[name];
    // A smaller page and figure than the others': each pixel marches the series, seconds a
    // frame on SwiftShader.
    const { page } = await open('?figure=320x240', { width: 900, height: 600 });
    await page.waitForFunction(() => document.body.dataset.state === 'ready', null, { timeout: LONG });
    await page.setInputFiles('#file', file);
    const src = await figureOf(page);
    fs.writeFileSync(path.join(out, 'web_odf_320x240.png'), Buffer.from(src.split(',')[1], 'base64'));
    const cmp = await compare(page, src, nativeFigure('odf', [file], '320x240'));
    const frac = cmp.close / cmp.n;
    check(!cmp.size && (await text(page, 'error')) === '', `the CSD fit opens as ODF glyphs (${cmp.size || 'no error'})`);
    check(frac >= 0.99, `its figure matches the native render: ${(100 * frac).toFixed(4)} % of pixels within 3/255`);
    // The status counts the series the file holds (every voxel sh2peaks found peaks in), not the
    // empty tensor set's 0 ("16 of 0 glyphs" before).
    await statusMatching(page, new RegExp(`^\\d+ of ${Object.keys(truth.peaks).length} glyphs · `));
    const box = await page.locator('#view').boundingBox();
    let seen = null;
    let last = '';
    for (let i = 0; i < 96 && !seen; i++) {
      const [fx, fy] = [0.3 + 0.65 * ((i * 5) % 24) / 24, 0.1 + 0.8 * ((i * 7) % 32) / 32];
      await page.mouse.move(box.x + box.width * fx, box.y + box.height * fy);
      await page.waitForTimeout(400);
      const pick = await text(page, 'pick');
      last = pick || last;
      const v = /^voxel #(\d+)/.exec(pick);
      const top = /\n\s+1: \(([-+\d.]+), ([-+\d.]+), ([-+\d.]+)\)/.exec(pick);
      const t = v && truth.peaks[v[1]];
      if (t && top && /SH lmax 8/.test(pick)) {
        const k = t.values.indexOf(Math.max(...t.values));
        seen = { voxel: v[1], got: top.slice(1, 4).map(Number), want: t.directions[k] };
      }
    }
    check(seen !== null, `hovering finds an ODF glyph (${seen ? `voxel #${seen.voxel}` : `none; last pick "${last.split('\n')[0]}"`})`);
    if (seen) {
      const cos = Math.abs(seen.got.reduce((s, x, k) => s + x * seen.want[k], 0)) /
        (Math.hypot(...seen.got) * Math.hypot(...seen.want));
      const deg = (Math.acos(Math.min(cos, 1)) * 180) / Math.PI;
      check(deg < 1, `its largest peak is sh2peaks', in world axes: ${deg.toFixed(3)}°`);
    }
    await page.screenshot({ path: path.join(out, 'page_odf.png') });
    await page.close();
  }

  // Peaks: MRtrix's sh2peaks image of the same fit opens as sticks whose figure is that of
  // `tensorglyph render FILE` (the same bound), and the status counts its peaks (three in each
  // of its 64 voxels).
  {
    const file = path.join(repo, 'tests/data/sh/sh2peaks_lmax8.mif');
    const { page } = await open('?figure=320x240', { width: 900, height: 600 });
    await page.waitForFunction(() => document.body.dataset.state === 'ready', null, { timeout: LONG });
    await page.setInputFiles('#file', file);
    const src = await figureOf(page);
    fs.writeFileSync(path.join(out, 'web_peaks_320x240.png'), Buffer.from(src.split(',')[1], 'base64'));
    const cmp = await compare(page, src, nativeFigure('peaks', [file], '320x240'));
    const frac = cmp.close / cmp.n;
    check(!cmp.size && (await text(page, 'error')) === '', `the sh2peaks image opens as sticks (${cmp.size || 'no error'})`);
    check(frac >= 0.99, `its figure matches the native render: ${(100 * frac).toFixed(4)} % of pixels within 3/255`);
    await statusMatching(page, /^48 of 192 glyphs · /);
    await page.screenshot({ path: path.join(out, 'page_peaks.png') });
    await page.close();
  }

  // BEP016: a map and its sidecar given together. The sidecar's ReferenceAxes (xyz: sub-02's
  // tensors are in scanner axes) decides the frame: a picked glyph's principal direction is
  // numpy's world one (tests/data/bids/make_bids.py), where reading the tensors in voxel axes
  // (the default without a sidecar) would flip its x. Glyphs whose direction has |x| > 0.3 are
  // the ones that tell (|cos| ≤ 0.82 in the wrong frame).
  {
    const bids = path.join(repo, 'tests/data/bids');
    const key = 'sub-02/dwi/sub-02_model-DTI_param-tensor_dwimap.nii.gz';
    const truth = JSON.parse(fs.readFileSync(path.join(bids, 'expected.json')))[key];
    const files = ['sub-02_model-DTI_param-tensor_dwimap.nii.gz', 'sub-02_model-DTI_dwimap.json'];
    const { page } = await open('');
    await page.waitForFunction(() => document.body.dataset.state === 'ready', null, { timeout: LONG });
    await page.setInputFiles('#file', files.map((f) => path.join(bids, 'derivatives/sub-02/dwi', f)));
    await statusMatching(page, new RegExp(`(^| of )${truth.fa.length} glyphs · `));
    check((await text(page, 'error')) === '', `${files.join(' + ')} open: "${await text(page, 'status')}"`);
    const box = await page.locator('#view').boundingBox();
    let telling = null;
    for (let i = 0; i < 48 && !telling; i++) {
      // A lattice over the view's part of the canvas (the panel is on the left).
      const [fx, fy] = [0.4 + 0.5 * ((i * 5) % 12) / 12, 0.15 + 0.7 * ((i * 7) % 16) / 16];
      await page.mouse.move(box.x + box.width * fx, box.y + box.height * fy);
      await page.waitForTimeout(600);
      const pick = await text(page, 'pick');
      if (!pick.includes('λ')) continue;
      const lines = pick.split('\n');
      const index = Number(lines[0].replace('glyph #', ''));
      const want = truth.e1_world[index];
      if (want && Math.abs(want[0]) > 0.3 && truth.fa[index] > 0.3) {
        telling = { index, want, t: lines.slice(3, 6).flatMap((l) => l.trim().split(/\s+/).map(Number)) };
      }
    }
    check(telling !== null, `hovering finds a glyph whose frame tells (${telling ? `glyph #${telling.index}` : 'none'})`);
    if (telling) {
      const e1 = jacobiEigen(telling.t)[0].vector;
      const cos = Math.abs(e1.reduce((s, x, k) => s + x * telling.want[k], 0));
      check(cos >= 0.99, `its principal direction is numpy's in the sidecar's frame (|cos| = ${cos.toFixed(5)})`);
    }
    await page.screenshot({ path: path.join(out, 'page_bep016.png') });
    await page.close();
  }

  // A browser without WebGPU (Chromium without the flags above has no adapter): a message naming
  // browsers that have it, not a blank page.
  {
    const plain = await chromium.launch({ executablePath: chromiumPath, args: ['--no-sandbox'] });
    const page = await plain.newPage();
    await page.goto(base + '?demo=grid40');
    await page.waitForFunction(() => document.getElementById('error').textContent !== '', null, { timeout: LONG });
    const message = await text(page, 'error');
    check(/WebGPU/.test(message) && /Chrome/.test(message) && /Safari/.test(message) && /Firefox/.test(message),
      `without WebGPU the page says so: "${message}"`);
    await plain.close();
  }
} catch (e) {
  check(false, `the page did what was asked (${e.message.split('\n')[0]})`);
} finally {
  await browser.close();
  server.close();
}

if (failures.length) {
  console.error(`${failures.length} check(s) failed`);
  process.exit(1);
}
console.log(`all checks passed; screenshots in ${out}`);

// Eigenvalues of a symmetric 3x3 matrix (row-major), largest first.
function jacobiEigenvalues(m) {
  return jacobiEigen(m).map((e) => e.value);
}

// Eigenpairs { value, vector } of a symmetric 3x3 matrix (row-major), largest value first:
// cyclic Jacobi rotations A := Jᵀ A J, accumulated in V := V J (the eigenvectors are its columns).
function jacobiEigen(m) {
  const a = [[m[0], m[1], m[2]], [m[3], m[4], m[5]], [m[6], m[7], m[8]]];
  const v = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];
  for (let sweep = 0; sweep < 50; sweep++) {
    for (const [p, q] of [[0, 1], [0, 2], [1, 2]]) {
      if (Math.abs(a[p][q]) < 1e-300) continue;
      const theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
      const t = Math.sign(theta || 1) / (Math.abs(theta) + Math.sqrt(theta * theta + 1));
      const c = 1 / Math.sqrt(t * t + 1);
      const s = t * c;
      for (const x of [a, v]) {
        for (let k = 0; k < 3; k++) {
          const [xkp, xkq] = [x[k][p], x[k][q]];
          x[k][p] = c * xkp - s * xkq;
          x[k][q] = s * xkp + c * xkq;
        }
      }
      for (let k = 0; k < 3; k++) {
        const [apk, aqk] = [a[p][k], a[q][k]];
        a[p][k] = c * apk - s * aqk;
        a[q][k] = s * apk + c * aqk;
      }
    }
  }
  return [0, 1, 2]
    .map((i) => ({ value: a[i][i], vector: [v[0][i], v[1][i], v[2][i]] }))
    .sort((x, y) => y.value - x.value);
}
