// A static file server for the playground (no dependencies): `node web/serve.mjs [port]` serves
// web/ on http://127.0.0.1:<port>/ (default 8000). The tests import `serve` and use port 0.
import { createServer } from 'node:http';
import { readFile } from 'node:fs/promises';
import { extname, join, normalize, sep } from 'node:path';
import { fileURLToPath } from 'node:url';

const ROOT = fileURLToPath(new URL('.', import.meta.url));
const TYPES = {
    '.html': 'text/html; charset=utf-8',
    '.js': 'text/javascript; charset=utf-8',
    '.css': 'text/css; charset=utf-8',
    '.wasm': 'application/wasm',
    '.json': 'application/json',
    '.png': 'image/png',
};

/// Starts serving web/ on 127.0.0.1:`port` (0: any free port); resolves to the server.
export function serve(port = 0) {
    const server = createServer(async (request, response) => {
        const path = decodeURIComponent(new URL(request.url, 'http://x').pathname);
        const file = normalize(join(ROOT, path.endsWith('/') ? path + 'index.html' : path));
        if (!file.startsWith(ROOT.endsWith(sep) ? ROOT : ROOT + sep)) {
            response.writeHead(403).end();
            return;
        }
        try {
            const body = await readFile(file);
            response.writeHead(200, { 'content-type': TYPES[extname(file)] ?? 'application/octet-stream' }).end(body);
        } catch {
            response.writeHead(404).end('not found');
        }
    });
    return new Promise((resolve) => server.listen(port, '127.0.0.1', () => resolve(server)));
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
    const server = await serve(Number(process.argv[2] ?? 8000));
    console.log(`the playground: http://127.0.0.1:${server.address().port}/`);
}
