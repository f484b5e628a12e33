// Opens each patchwork .glb in three.js (GLTFLoader) in headless Chromium,
// renders it through the camera the file carries (the one patchwork's own
// renderer used) and compares the picture with patchwork's rendering of the
// same result (a PPM written by the same command).
//
// Usage: node view.mjs OUT_DIR NAME.glb:NAME.ppm[:AMBIENT] ...
// Prints "PASS|FAIL gltf_view/NAME: ..." and writes OUT_DIR/NAME.three.ppm
// (three.js's picture) and OUT_DIR/NAME.diff.ppm (the difference, x4).
//
// The measure: both pictures low-passed by a 5x5 box, then the mean
// absolute colour difference (0..255, per channel, over pixels either
// picture covers) and the 99th percentile of the per-pixel largest channel
// difference. The blur removes what two correct renderers may differ in
// -- which mip level a texel footprint picks (patchwork's trilinear
// filtering against the GPU's) and how edges are antialiased -- and keeps
// what a wrong file shows: a texture mapped the wrong way, wrong normals
// (shading), a wrong camera (silhouettes). The unblurred figures are
// reported too. Negative control: the same file drawn with the texture's v
// flipped must fail the bounds, or the check is too weak to trust.
//
// three.js draws the file's own data: geometry, normals, texture
// coordinates, the embedded PNG and the sampler. Only the shading is set
// here to patchwork's (Lambert with a light from the camera's direction
// (-0.3, 0.4, 1), ambient AMBIENT, default 0.3, colours taken linearly),
// because a glTF material's PBR shading would differ from patchwork's by
// design, not by error.
import { createServer } from 'node:http';
import { readFile, writeFile } from 'node:fs/promises';
import { basename, dirname, extname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import puppeteer from 'puppeteer-core';

const here = dirname(fileURLToPath(import.meta.url));
const MEAN_MAX = 3.0;  // blurred: mean |difference| per channel, 0..255
const P99_MAX = 24.0;  // blurred: 99th percentile of the per-pixel largest channel difference
const RADIUS = 2;      // the box blur's radius (5x5)

function readPPM(buf) {
    let pos = 0;
    const tok = () => {
        while (buf[pos] === 0x23 || buf[pos] <= 0x20) {
            if (buf[pos] === 0x23) while (buf[pos] !== 0x0a) pos++;
            else pos++;
        }
        const s = pos;
        while (buf[pos] > 0x20) pos++;
        return buf.toString('latin1', s, pos);
    };
    if (tok() !== 'P6') throw new Error('not a binary PPM');
    const w = +tok(), h = +tok(), max = +tok();
    if (max !== 255) throw new Error('PPM maxval is not 255');
    pos++;
    return { w, h, px: buf.subarray(pos, pos + w * h * 3) };
}

// Mean and 99th percentile of the differences of a and b (RGB, w x h),
// both box-blurred with radius r first, over pixels either covers (not the
// white background in both).
function compare(a, b, w, h, r) {
    const A = blur(a, w, h, r), B = blur(b, w, h, r), worst = [];
    let sum = 0;
    for (let i = 0; i < w * h; i++) {
        if (a[3 * i] === 255 && a[3 * i + 1] === 255 && a[3 * i + 2] === 255 &&
            b[3 * i] === 255 && b[3 * i + 1] === 255 && b[3 * i + 2] === 255) continue;
        let m = 0;
        for (let k = 0; k < 3; k++) {
            const d = Math.abs(A[3 * i + k] - B[3 * i + k]);
            sum += d;
            m = Math.max(m, d);
        }
        worst.push(m);
    }
    worst.sort((x, y) => x - y);
    const n = worst.length;
    return { n, mean: n ? sum / (3 * n) : 255, p99: n ? worst[Math.floor(0.99 * (n - 1))] : 255 };
}

function blur(px, w, h, r) {
    if (!r) return px;
    const tmp = new Float32Array(w * h * 3), out = new Float32Array(w * h * 3);
    for (let y = 0; y < h; y++)
        for (let x = 0; x < w; x++)
            for (let k = 0; k < 3; k++) {
                let s = 0, n = 0;
                for (let d = -r; d <= r; d++) if (x + d >= 0 && x + d < w) s += px[3 * (y * w + x + d) + k], n++;
                tmp[3 * (y * w + x) + k] = s / n;
            }
    for (let y = 0; y < h; y++)
        for (let x = 0; x < w; x++)
            for (let k = 0; k < 3; k++) {
                let s = 0, n = 0;
                for (let d = -r; d <= r; d++) if (y + d >= 0 && y + d < h) s += tmp[3 * ((y + d) * w + x) + k], n++;
                out[3 * (y * w + x) + k] = s / n;
            }
    return out;
}

function writePPM(w, h, px) {
    return Buffer.concat([Buffer.from(`P6\n${w} ${h}\n255\n`), Buffer.from(px)]);
}

const types = { '.html': 'text/html', '.js': 'text/javascript', '.glb': 'model/gltf-binary' };
function serve(files) {
    const server = createServer(async (req, res) => {
        const url = decodeURIComponent(req.url.split('?')[0]);
        let path = null;
        if (url === '/') path = join(here, 'view.html');
        else if (url.startsWith('/three/')) path = join(here, 'node_modules', url.slice(1));
        else if (files.has(url.slice(1))) path = files.get(url.slice(1));
        if (!path || path.includes('..')) { res.writeHead(404); res.end(); return; }
        try {
            const data = await readFile(path);
            res.writeHead(200, { 'Content-Type': types[extname(path)] || 'application/octet-stream' });
            res.end(data);
        } catch { res.writeHead(404); res.end(); }
    });
    return new Promise((ok) => server.listen(0, '127.0.0.1', () => ok(server)));
}

const [outDir, ...jobs] = process.argv.slice(2);
const files = new Map();
const list = jobs.map((j) => {
    const [glb, ppm, ambient] = j.split(':');
    files.set(basename(glb), glb);
    return { glb, ppm, ambient: ambient ? +ambient : 0.3, name: basename(glb, '.glb') };
});
const server = await serve(files);
const browser = await puppeteer.launch({
    executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
    headless: true,
    args: ['--headless=new', '--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'],
});
let failed = 0;
try {
    const page = await browser.newPage();
    page.on('pageerror', (err) => console.log(`INFO gltf_view: page error: ${err}`));
    await page.goto(`http://127.0.0.1:${server.address().port}/`);
    await page.waitForFunction('window.renderGlb !== undefined', { timeout: 30000 });
    for (const job of list) {
        const ref = readPPM(await readFile(job.ppm));
        const got = await page.evaluate((u, w, h, a) => window.renderGlb(u, w, h, a), basename(job.glb), ref.w, ref.h, job.ambient);
        if (got.error) {
            console.log(`FAIL gltf_view/${job.name}: three.js: ${got.error}`);
            failed++;
            continue;
        }
        const px = Buffer.from(got.rgb, 'base64');
        const raw = compare(ref.px, px, ref.w, ref.h, 0), soft = compare(ref.px, px, ref.w, ref.h, RADIUS);
        const flipped = await page.evaluate((u, w, h, a) => window.renderGlb(u, w, h, a, true), basename(job.glb), ref.w, ref.h, job.ambient);
        const control = flipped.error ? null : compare(ref.px, Buffer.from(flipped.rgb, 'base64'), ref.w, ref.h, RADIUS);
        const diff = new Uint8Array(ref.w * ref.h * 3);
        for (let i = 0; i < diff.length; i++) diff[i] = Math.min(255, 4 * Math.abs(ref.px[i] - px[i]));
        await writeFile(join(outDir, `${job.name}.three.ppm`), writePPM(ref.w, ref.h, px));
        await writeFile(join(outDir, `${job.name}.diff.ppm`), writePPM(ref.w, ref.h, diff));
        const within = (m) => m.n > 0 && m.mean <= MEAN_MAX && m.p99 <= P99_MAX;
        const line = `blurred: mean difference ${soft.mean.toFixed(2)}/255 (bound ${MEAN_MAX}), 99th percentile ` +
            `${soft.p99.toFixed(1)}/255 (bound ${P99_MAX}); unblurred ${raw.mean.toFixed(2)} and ${raw.p99.toFixed(1)}; ` +
            `over ${soft.n} covered pixels; v flipped (control): ${control ? control.mean.toFixed(2) + ' and ' + control.p99.toFixed(1) : 'not drawn'}; ` +
            `${got.triangles} triangles, renderer "${got.renderer}"`;
        const ok = within(soft) && control && !within(control);
        if (!ok) failed++;
        console.log(`${ok ? 'PASS' : 'FAIL'} gltf_view/${job.name}${ok ? '' : ': ' + line}`);
        if (ok) console.log(`INFO gltf_view/${job.name}: ${line}`);
    }
} finally {
    await browser.close();
    server.close();
}
process.exit(failed ? 1 : 0);
