// Drives the playground (web/, built by scripts/web) in headless Chromium over the DevTools
// protocol (playwright-core, pointed at Debian's chromium-headless-shell; it downloads no
// browser), as a user would: pick a preset, set the lighting, break the material, fix it, move a
// slider. Prints one JSON report of what it saw; crates/glazec-web/tests/browser.rs judges it.
//
// Usage: node tests/browser/run.mjs job.json, where the job gives
//   chromium: the browser binary; preset: the material to show; lighting: the controls' values
//   for the pixel check; centre: [x, y] of the pixel; outside: [x, y] off the sphere;
//   break: { from, to }, a replacement that breaks the preset's text; slider: { param, component,
//   value, reset };
//   extra: more texts to type in, each must render; lit: [x, y] of a pixel each material lights;
//   timing: the text whose compile time is measured in the page; screenshot: a PNG path or null.

import { readFileSync } from 'node:fs';
import { chromium } from 'playwright-core';
import { serve } from '../../web/serve.mjs';

const job = JSON.parse(readFileSync(process.argv[2], 'utf8'));
const report = { log: [] };
const server = await serve(0);
const browser = await chromium.launch({
    executablePath: job.chromium,
    headless: true,
    // SwiftShader's WebGPU adapter, and SwiftShader's Vulkan under the compositor (with GL,
    // headless Chromium 156 loses the WebGPU device at a canvas's first getCurrentTexture); no
    // calls to Google's services (this machine has no network).
    args: [
        '--no-sandbox',
        '--enable-unsafe-webgpu',
        '--use-angle=swiftshader',
        '--enable-features=Vulkan',
        '--use-vulkan=swiftshader',
        '--disable-background-networking',
        '--disable-component-update',
        '--disable-sync',
        '--disable-quic',
        '--no-first-run',
    ],
});

try {
    const page = await browser.newPage({ viewport: { width: 1320, height: 900 } });
    page.on('console', (m) => report.log.push(`${m.type()}: ${m.text()}`));
    page.on('pageerror', (e) => report.log.push(`page error: ${e.message}`));
    const url = `http://127.0.0.1:${server.address().port}/`;
    await page.goto(url);
    const settled = () =>
        page.waitForFunction(() => window.playground && window.playground.state !== 'loading', null, { timeout: 180_000 });
    const state = () => page.evaluate(() => ({ state: playground.state, renders: playground.renders, present: playground.present, last: playground.last, status: document.getElementById('status').textContent }));
    const rendered = (after) =>
        page.waitForFunction((n) => playground.state === 'ready' && playground.renders > n, after, { timeout: 60_000 });
    const pixel = ([x, y]) => page.evaluate(([x, y]) => playground.pixel(x, y), [x, y]);
    const setInput = (selector, value) =>
        page.$eval(selector, (el, v) => {
            if (el.type === 'checkbox') {
                el.checked = v;
                el.dispatchEvent(new Event('change', { bubbles: true }));
            } else {
                el.value = String(v);
                el.dispatchEvent(new Event('input', { bubbles: true }));
            }
        }, value);

    await settled();
    report.start = await state();
    report.adapter = await page.evaluate(() => playground.adapter);

    // A preset renders.
    const before = report.start.renders;
    await page.selectOption('#preset', job.preset);
    await rendered(before);
    for (const [key, value] of Object.entries(job.lighting)) await setInput(`#${key}`, value);
    report.preset = await state();
    report.lighting = await page.evaluate(() => playground.renderer.lighting);
    report.centre = await pixel(job.centre);
    report.outside = await pixel(job.outside);
    report.params = await page.$$eval('#params input', (inputs) => inputs.map((i) => i.dataset.param + (i.dataset.component ? '.' + i.dataset.component : '')));

    // An edit that breaks the material: its diagnostic, at its line, with its code.
    const original = await page.inputValue('#source');
    if (!original.includes(job.break.from)) throw new Error(`the preset does not contain ${JSON.stringify(job.break.from)}`);
    await page.fill('#source', original.replace(job.break.from, job.break.to));
    await page.waitForFunction(() => playground.state === 'invalid', null, { timeout: 60_000 });
    report.broken = {
        state: await state(),
        diagnostics: await page.$$eval('#diagnostics li', (items) => items.map((li) => ({ code: li.dataset.code, line: Number(li.dataset.line), text: li.textContent }))),
        marks: await page.$$eval('#backdrop mark', (marks) => marks.map((m) => ({ text: m.textContent, line: Number(m.dataset.line) }))),
        flagged: await page.$$eval('#gutter span.error', (spans) => spans.map((s) => Number(s.textContent))),
    };

    // Fixing it renders again.
    const renders = (await state()).renders;
    await page.fill('#source', original);
    await rendered(renders);
    report.fixed = { state: await state(), centre: await pixel(job.centre), marks: await page.$$eval('#backdrop mark', (m) => m.length) };

    // Every preset, and each extra text typed in (a textured material), renders.
    report.presets = {};
    const presetNames = await page.$$eval('#preset option', (options) => options.map((o) => o.value));
    const texts = [...presetNames.map((name) => ({ name })), ...job.extra.map((text, i) => ({ name: `extra ${i}`, text }))];
    for (const { name, text } of texts) {
        const n = (await state()).renders;
        if (text === undefined) await page.selectOption('#preset', name);
        else await page.fill('#source', text);
        await page.waitForFunction((n) => playground.renders > n || ['invalid', 'error'].includes(playground.state), n, { timeout: 60_000 });
        const s = await state();
        report.presets[name] = { state: s.state, status: s.status, lit: await pixel(job.lit) };
    }
    await page.selectOption('#preset', job.preset);
    await rendered((await state()).renders);

    // A slider changes the image.
    const s = job.slider;
    await setInput(`#params input[data-param="${s.param}"][data-component="${s.component}"]`, s.value);
    report.slider = { centre: await pixel(job.centre) };

    // The other way of presenting (a texture copied into a 2D canvas) draws the same pixels.
    const readback = await browser.newPage({ viewport: { width: 1320, height: 900 } });
    readback.on('pageerror', (e) => report.log.push(`page error (readback): ${e.message}`));
    await readback.goto(`${url}?present=readback`);
    await readback.waitForFunction((name) => window.playground?.state === 'ready' && playground.last?.name === name, job.preset, { timeout: 180_000 });
    report.readback = await readback.evaluate(async ([lighting, centre]) => {
        Object.assign(playground.renderer.lighting, lighting);
        return { present: playground.present, centre: await playground.pixel(...centre) };
    }, [job.lighting, job.centre]);
    await readback.close();

    // The compile time of a material in this browser: the median of repeated `compile` calls.
    report.timing = await page.evaluate((text) => {
        const times = [];
        for (let i = 0; i < 30; i++) {
            const start = performance.now();
            const out = playground.compile(text);
            times.push(performance.now() - start);
            if (!out.ok) throw new Error('the timed material did not compile');
        }
        times.sort((a, b) => a - b);
        return { median_ms: times[15], fastest_ms: times[0], runs: times.length };
    }, job.timing);

    if (job.screenshot) {
        await setInput(`#params input[data-param="${s.param}"][data-component="${s.component}"]`, s.reset);
        await setInput('#environment', 1);
        await setInput('#tonemap', true);
        await setInput('#intensity', 3);
        await page.selectOption('#preset', job.screenshot_preset);
        const n = (await state()).renders;
        await rendered(n);
        await page.click('nav button[data-tab="wgsl"]');
        await page.screenshot({ path: job.screenshot });
    }
} catch (e) {
    report.error = String(e.stack ?? e);
} finally {
    await browser.close();
    server.close();
}
console.log(JSON.stringify(report));
