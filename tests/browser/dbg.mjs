import { chromium } from 'playwright-core';
import { serve } from '/work/main/web/serve.mjs';
const server = await serve(0);
const browser = await chromium.launch({ executablePath: '/usr/lib/chromium/chromium-headless-shell', headless: true, args: ['--no-sandbox','--enable-unsafe-webgpu','--disable-background-networking','--enable-logging=stderr','--v=0'] });
const page = await browser.newPage();
page.on('console', (m) => console.log('console', m.type(), m.text()));
await page.addInitScript(() => { window.__t0 = performance.now(); });
await page.goto(`http://127.0.0.1:${server.address().port}/`);
await page.waitForFunction(() => window.playground && window.playground.state !== 'loading', null, { timeout: 180000 });
console.log(await page.evaluate(async () => {
  const steps = [playground.state, document.getElementById('status').textContent];
  const d = playground.renderer.device;
  let lost = 'not lost'; d.lost.then((i) => lost = 'LOST ' + i.reason + ' ' + i.message);
  try {
    const m = d.createShaderModule({ code: '@fragment fn f() -> @location(0) vec4f { return vec4f(1); }' });
    steps.push('info ' + (await m.getCompilationInfo()).messages.length);
  } catch (e) { steps.push('ERR ' + e.message); }
  await new Promise(r => setTimeout(r, 100)); steps.push(lost);
  return steps;
}));
await browser.close(); server.close();
