// Runs glazec's WGSL through Dawn (Chrome's WebGPU implementation, npm package `webgpu`), for
// tests/webgpu.rs. Usage: node check.mjs <job.json>; prints one JSON object on stdout.
//
// job.check: [{ name, file, entries: [{ name, stage }] }] — every module is compiled by Tint
//   (createShaderModule + getCompilationInfo) on Dawn's `null` backend (no GPU needed) and a
//   pipeline is built for each entry point (layout 'auto'); every message is reported.
// job.run: [{ name, file, count, pairs, params, tables }] — `eval_pairs` executed on Dawn's
//   OpenGL ES backend (llvmpipe, EGL_PLATFORM=surfaceless, feature level 'compatibility'):
//   `pairs`, `params` and `tables` are byte arrays; the values (4 floats a pair) come back.
// job.backend: 'null' or 'opengles'.
import fs from 'node:fs';
import { create, globals } from 'webgpu';

Object.assign(globalThis, globals);
const job = JSON.parse(fs.readFileSync(process.argv[2], 'utf8'));
// Kept for the program's lifetime: Dawn aborts if the instance is garbage-collected.
const gpu = create([`backend=${job.backend}`]);
const adapter = await gpu.requestAdapter(job.backend === 'opengles' ? { featureLevel: 'compatibility' } : {});
if (!adapter) {
  console.log(JSON.stringify({ error: `no ${job.backend} adapter` }));
  process.exit(0);
}
// The table uniforms of the default method exceed the 16 KiB that WebGPU guarantees; ask for what
// the adapter has.
const device = await adapter.requestDevice({
  requiredLimits: { maxUniformBufferBindingSize: adapter.limits.maxUniformBufferBindingSize },
});
const errors = [];
device.addEventListener('uncapturederror', (e) => errors.push(e.error.message));

const out = { messages: [], modules: 0, pipelines: 0, results: {}, errors };
const compile = async (name, file) => {
  const module = device.createShaderModule({ label: name, code: fs.readFileSync(file, 'utf8') });
  const info = await module.getCompilationInfo();
  for (const m of info.messages) {
    out.messages.push({ name, type: m.type, line: m.lineNum, column: m.linePos, message: m.message });
  }
  out.modules++;
  return module;
};

for (const item of job.check ?? []) {
  const module = await compile(item.name, item.file);
  for (const entry of item.entries) {
    device.pushErrorScope('validation');
    try {
      if (entry.stage === 'compute') {
        await device.createComputePipelineAsync({ layout: 'auto', compute: { module, entryPoint: entry.name } });
      } else if (entry.stage === 'fragment') {
        await device.createRenderPipelineAsync({
          layout: 'auto',
          vertex: { module, entryPoint: 'preview_vs', buffers: [{ arrayStride: 8, attributes: [{ shaderLocation: 0, offset: 0, format: 'float32x2' }] }] },
          fragment: { module, entryPoint: entry.name, targets: [{ format: 'rgba16float' }] },
        });
      }
      out.pipelines++;
    } catch (e) {
      out.messages.push({ name: `${item.name}:${entry.name}`, type: 'error', message: String(e.message ?? e) });
    }
    const error = await device.popErrorScope();
    if (error) out.messages.push({ name: `${item.name}:${entry.name}`, type: 'error', message: error.message });
  }
}

const bytes = (array) => new Uint8Array(array);
const buffer = (data, usage) => {
  const b = device.createBuffer({ size: Math.max(16, Math.ceil(data.byteLength / 4) * 4), usage, mappedAtCreation: true });
  new Uint8Array(b.getMappedRange()).set(data);
  b.unmap();
  return b;
};
for (const item of job.run ?? []) {
  const module = await compile(item.name, item.file);
  const pipeline = await device.createComputePipelineAsync({ layout: 'auto', compute: { module, entryPoint: 'eval_pairs' } });
  const size = item.count * 16;
  const values = device.createBuffer({ size, usage: GPUBufferUsage.STORAGE | GPUBufferUsage.COPY_SRC });
  const readback = device.createBuffer({ size, usage: GPUBufferUsage.MAP_READ | GPUBufferUsage.COPY_DST });
  const dispatch = new Uint32Array([item.count, 0, 0, 0]);
  const entries = [
    { binding: item.bindings.pairs, resource: { buffer: buffer(bytes(item.pairs), GPUBufferUsage.STORAGE) } },
    { binding: item.bindings.values, resource: { buffer: values } },
    { binding: item.bindings.dispatch, resource: { buffer: buffer(new Uint8Array(dispatch.buffer), GPUBufferUsage.UNIFORM) } },
  ];
  if (item.bindings.params !== null) entries.push({ binding: item.bindings.params, resource: { buffer: buffer(bytes(item.params), GPUBufferUsage.UNIFORM) } });
  if (item.bindings.tables !== null) entries.push({ binding: item.bindings.tables, resource: { buffer: buffer(bytes(item.tables), GPUBufferUsage.UNIFORM) } });
  const group = device.createBindGroup({ layout: pipeline.getBindGroupLayout(0), entries });
  const encoder = device.createCommandEncoder();
  const pass = encoder.beginComputePass();
  pass.setPipeline(pipeline);
  pass.setBindGroup(0, group);
  pass.dispatchWorkgroups(Math.ceil(item.count / 64));
  pass.end();
  encoder.copyBufferToBuffer(values, 0, readback, 0, size);
  device.queue.submit([encoder.finish()]);
  await readback.mapAsync(GPUMapMode.READ);
  out.results[item.name] = Array.from(new Float32Array(readback.getMappedRange().slice(0)));
  readback.unmap();
}
console.log(JSON.stringify(out));
process.exit(0);
