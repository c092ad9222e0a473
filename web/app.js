// The playground page: the editor, its diagnostics, the generated code, the parameter sliders
// and the WebGPU view. glazec itself runs here, compiled to WebAssembly (crates/glazec-web):
// every edit is checked and compiled in the page, nothing leaves the browser.

import init, { compile } from './pkg/glazec_web.js';
import presets from './pkg/presets.js';
import { Renderer } from './render.js';

const $ = (id) => document.getElementById(id);
const source = $('source');
const status = $('status');

/// What the tests and the console can read (window.playground).
const playground = {
    /// 'loading', 'ready' (the current text rendered), 'invalid' (diagnostics shown) or 'error'.
    state: 'loading',
    /// The last compilation: { ok, ms, name, diagnostics }.
    last: null,
    /// Bumped by every finished render of a new material.
    renders: 0,
    adapter: '',
    renderer: null,
    compile: (text) => JSON.parse(compile(text)),
};
window.playground = playground;

function setStatus(text, error = false) {
    status.textContent = text;
    status.classList.toggle('error', error);
}

// --- Diagnostics at their spans ---------------------------------------------------------------

/// The UTF-16 index (a textarea's) of UTF-8 byte offset `byte` (the compiler's) in `text`.
function byteToIndex(text, byte) {
    let bytes = 0;
    let index = 0;
    for (const ch of text) {
        if (bytes >= byte) break;
        const c = ch.codePointAt(0);
        bytes += c < 0x80 ? 1 : c < 0x800 ? 2 : c < 0x10000 ? 3 : 4;
        index += ch.length;
    }
    return index;
}

const escape = (s) => s.replace(/[&<>]/g, (c) => ({ '&': '&amp;', '<': '&lt;', '>': '&gt;' })[c]);

/// Draws the text's diagnostics: marks under their spans, flagged line numbers and the list.
function showDiagnostics(text, diagnostics) {
    const spans = [];
    for (const d of diagnostics) {
        for (const l of d.labels) {
            const start = byteToIndex(text, l.byte_start);
            // An empty span (the end of the text) still gets one visible character.
            const end = Math.max(byteToIndex(text, l.byte_end), start + 1);
            spans.push({ start, end, severity: d.severity, primary: l.primary });
        }
    }
    spans.sort((a, b) => a.start - b.start || b.primary - a.primary);
    let html = '';
    let at = 0;
    for (const s of spans) {
        if (s.start < at) continue; // overlapping labels: the first one is drawn
        html += escape(text.slice(at, s.start));
        const cls = s.severity === 'error' ? '' : ' class="warning"';
        html += `<mark${cls} data-line="${lineOf(text, s.start)}">${escape(text.slice(s.start, s.end) || ' ')}</mark>`;
        at = Math.min(s.end, text.length);
    }
    $('backdrop').innerHTML = html + escape(text.slice(at)) + '\n';

    const flagged = new Map(diagnostics.map((d) => [d.line, d.severity]));
    const lines = text.split('\n').length;
    $('gutter').innerHTML = Array.from({ length: lines }, (_, i) => {
        const severity = flagged.get(i + 1);
        return severity ? `<span class="${severity}">${i + 1}</span>` : `${i + 1}`;
    }).join('\n');

    const list = $('diagnostics');
    list.replaceChildren(
        ...diagnostics.map((d) => {
            const li = document.createElement('li');
            li.className = d.severity;
            li.dataset.code = d.code;
            li.dataset.line = d.line;
            const labels = d.labels.filter((l) => l.message).map((l) => `\n  ${l.start.line}:${l.start.column}: ${l.message}`);
            const notes = (d.notes ?? []).map((n) => `\n  = ${n}`);
            li.innerHTML = `<span class="code">${d.severity}[${d.code}]</span> line ${d.line}, column ${d.column}: ${escape(d.message)}${escape(labels.join(''))}${escape(notes.join(''))}`;
            const primary = d.labels.find((l) => l.primary) ?? d.labels[0];
            li.addEventListener('click', () => {
                if (!primary) return;
                source.focus();
                source.setSelectionRange(byteToIndex(text, primary.byte_start), byteToIndex(text, primary.byte_end));
            });
            return li;
        }),
    );
    syncScroll();
}

function lineOf(text, index) {
    let line = 1;
    for (let i = 0; i < index; i++) if (text.charCodeAt(i) === 10) line++;
    return line;
}

function syncScroll() {
    $('backdrop').scrollTop = source.scrollTop;
    $('backdrop').scrollLeft = source.scrollLeft;
    $('gutter').scrollTop = source.scrollTop;
}

// --- Generated code ---------------------------------------------------------------------------

const outputs = { wgsl: '', glsl: '', hlsl: '', harness: '' };
let tab = 'wgsl';

function showOutput() {
    $('output').textContent = outputs[tab];
    for (const b of document.querySelectorAll('nav button')) b.setAttribute('aria-selected', String(b.dataset.tab === tab));
}

// --- Parameters -------------------------------------------------------------------------------

/// The slider values the user set, by parameter name, kept across edits while the parameter's
/// shape and default stay the same.
const chosen = new Map();

/// A slider's span: the slot's range (compile's `range`), cut to a handy width for the wide ones
/// (absorption and thickness accept up to 10⁶).
function sliderRange(p) {
    const [lo, hi] = p.range;
    return [lo, Math.min(hi, Math.max(1, 2 * Math.max(...p.default)))];
}

function buildParams(out) {
    const box = $('params');
    box.querySelectorAll('label').forEach((l) => l.remove());
    box.querySelector('.none').hidden = out.params.length > 0;
    for (const p of out.params) {
        const key = `${p.name}:${p.default.join(',')}`;
        const value = chosen.get(key) ?? [...p.default];
        chosen.set(key, value);
        if (value.join() !== p.default.join()) playground.renderer.setParam(p.name, value);
        const [lo, hi] = sliderRange(p);
        const components = p.default.length === 3 ? ['r', 'g', 'b'] : [''];
        components.forEach((c, i) => {
            const label = document.createElement('label');
            const input = Object.assign(document.createElement('input'), { type: 'range', min: lo, max: hi, step: (hi - lo) / 500 });
            input.value = value[i];
            input.dataset.param = p.name;
            input.dataset.component = i;
            const output = document.createElement('output');
            output.textContent = value[i].toFixed(3);
            input.addEventListener('input', () => {
                value[i] = Number(input.value);
                output.textContent = value[i].toFixed(3);
                playground.renderer.setParam(p.name, value);
                playground.renderer.render();
            });
            label.append(`${p.name}${c ? '.' + c : ''}`, input, output);
            box.append(label);
        });
    }
}

function bindLighting() {
    const lighting = () => playground.renderer.lighting;
    for (const key of ['elevation', 'azimuth', 'intensity', 'environment', 'exposure']) {
        const input = $(key);
        const output = input.nextElementSibling;
        input.value = lighting()[key];
        output.textContent = input.value;
        input.addEventListener('input', () => {
            lighting()[key] = Number(input.value);
            output.textContent = input.value;
            playground.renderer.render();
        });
    }
    const tonemap = $('tonemap');
    tonemap.checked = lighting().tonemap;
    tonemap.addEventListener('change', () => {
        lighting().tonemap = tonemap.checked;
        playground.renderer.render();
    });
}

// --- Compiling on every edit ------------------------------------------------------------------

let generation = 0;

async function update() {
    const text = source.value;
    const mine = ++generation;
    const start = performance.now();
    const out = JSON.parse(compile(text));
    const ms = performance.now() - start;
    playground.last = { ok: out.ok, ms, name: out.name, diagnostics: out.diagnostics ?? [] };
    showDiagnostics(text, out.diagnostics ?? []);
    if (!out.ok) {
        const count = out.diagnostics.length;
        playground.state = 'invalid';
        setStatus(out.internal ? `glazec bug: ${out.internal}` : `${count} diagnostic${count === 1 ? '' : 's'} (checked in ${ms.toFixed(1)} ms); the view shows the last material that compiled`, true);
        return;
    }
    Object.assign(outputs, { wgsl: out.wgsl, glsl: out.glsl, hlsl: out.hlsl });
    const renderer = playground.renderer;
    if (!renderer) {
        showOutput();
        setStatus(`${out.name}: compiled to WGSL, GLSL and HLSL in ${ms.toFixed(1)} ms (no WebGPU: nothing to draw)`);
        return;
    }
    try {
        const pipelineStart = performance.now();
        const material = await renderer.prepare(out);
        if (mine !== generation) return; // a newer edit won the race
        renderer.material = material;
        outputs.harness = material.code.slice(out.wgsl.length + 1);
        showOutput();
        buildParams(out);
        await renderer.render();
        await renderer.device.queue.onSubmittedWorkDone();
        if (mine !== generation || playground.renderer !== renderer) return;
        playground.renders++;
        playground.state = 'ready';
        setStatus(`${out.name}: compiled to WGSL, GLSL and HLSL in ${ms.toFixed(1)} ms; pipeline ${(performance.now() - pipelineStart).toFixed(0)} ms`);
    } catch (e) {
        if (mine !== generation || playground.renderer !== renderer) return;
        playground.state = 'error';
        setStatus(`the browser rejected the shader: ${e.message}`, true);
    }
}

/// The canvas's pixel (x, y) as 8-bit sRGB [r, g, b, a], after a fresh frame.
playground.pixel = async (x, y) => {
    const renderer = playground.renderer;
    const canvas = renderer.canvas;
    if (renderer.present === 'readback') {
        await renderer.render();
        return Array.from(renderer.context2d.getImageData(x, y, 1, 1).data);
    }
    // A WebGPU canvas is read in the task that drew it.
    renderer.render();
    const copy = Object.assign(document.createElement('canvas'), { width: canvas.width, height: canvas.height });
    const ctx = copy.getContext('2d');
    ctx.drawImage(canvas, 0, 0);
    return Array.from(ctx.getImageData(x, y, 1, 1).data);
};

/// Starts the WebGPU view. If the device is lost while drawing into the canvas (headless
/// Chromium's SwiftShader under its default GL compositor cannot present), the view starts
/// again on a fresh canvas, presenting through a readback (render.js), where an adapter is
/// left; `?present=readback` starts that way.
async function startRenderer(present) {
    const old = playground.renderer;
    let canvas = $('view');
    if (old) {
        // A canvas keeps its first context: a fresh one for the new one.
        const fresh = canvas.cloneNode(false);
        canvas.replaceWith(fresh);
        canvas = fresh;
    }
    const renderer = await Renderer.create(canvas, present);
    if (old) renderer.lighting = old.lighting;
    playground.renderer = renderer;
    playground.adapter = renderer.adapter;
    playground.present = present;
    renderer.device.lost.then(async (info) => {
        if (playground.renderer !== renderer) return;
        console.warn(`WebGPU device lost (${info.reason}): ${info.message}`);
        try {
            if (present !== 'canvas') throw new Error(info.message);
            await startRenderer('readback');
            await update();
        } catch (e) {
            playground.state = 'error';
            setStatus(`WebGPU device lost: ${e.message} (try ?present=readback)`, true);
        }
    });
}

async function main() {
    await init();
    const select = $('preset');
    for (const name of Object.keys(presets)) select.append(new Option(name, name));
    select.value = 'tunable_glaze' in presets ? 'tunable_glaze' : Object.keys(presets)[0];
    source.value = presets[select.value];
    select.addEventListener('change', () => {
        source.value = presets[select.value];
        update();
    });
    source.addEventListener('input', update);
    source.addEventListener('scroll', syncScroll);
    source.addEventListener('keydown', (e) => {
        if (e.key !== 'Tab') return;
        e.preventDefault();
        source.setRangeText('    ', source.selectionStart, source.selectionEnd, 'end');
        update();
    });
    for (const b of document.querySelectorAll('nav button')) {
        b.addEventListener('click', () => {
            tab = b.dataset.tab;
            showOutput();
        });
    }
    try {
        await startRenderer(new URLSearchParams(location.search).get('present') === 'readback' ? 'readback' : 'canvas');
        bindLighting();
    } catch (e) {
        console.error(e);
        setStatus(`no WebGPU view: ${e.message}`, true);
    }
    await update();
}

main().catch((e) => {
    playground.state = 'error';
    setStatus(`the playground failed to start: ${e.message}`, true);
});
