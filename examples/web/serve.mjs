// A static server for the three.js example and the browser tests, on 127.0.0.1 only.
//   node examples/web/serve.mjs [--port N] [--package DIR] [--node-modules DIR] [--assets DIR]
// Routes: /examples/web/ (this folder), /package/ (scripts/build-web's package), /three/
// (the three npm package), /assets/ (characters, recorded lines), /tests/web/ (trace runner).
// Import it to start one from a test: startServer({...}) -> {url, close()}.
import { createServer } from 'node:http';
import { readFile, stat } from 'node:fs/promises';
import { extname, join, normalize, resolve, sep } from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const here = fileURLToPath(new URL('.', import.meta.url));
const root = resolve(here, '..', '..');
const TYPES = { '.html': 'text/html', '.mjs': 'text/javascript', '.js': 'text/javascript', '.json': 'application/json',
  '.wasm': 'application/wasm', '.glb': 'model/gltf-binary', '.vrm': 'model/gltf-binary', '.wav': 'audio/wav',
  '.ts': 'text/plain', '.lab': 'text/plain', '.txt': 'text/plain', '.png': 'image/png', '.css': 'text/css' };

export async function startServer({ port = 0, packageDir = join(root, 'build-web', 'package'),
  nodeModules = join(process.env.HOME || '', '.cache', 'marionette', 'tools', 'node_modules'),
  assets = join(root, '..', 'shared', 'assets') } = {}) {
  const routes = [['/examples/web/', here], ['/package/', packageDir], ['/three/', join(nodeModules, 'three')],
    ['/assets/', assets], ['/tests/web/', join(root, 'tests', 'web')]];
  const server = createServer(async (req, res) => {
    let path;
    try {
      path = decodeURIComponent(new URL(req.url, 'http://x').pathname);
    } catch {
      res.writeHead(400);
      res.end('bad request');
      return;
    }
    const route = routes.find(([prefix]) => path.startsWith(prefix));
    if (path === '/' || path === '/index.html') {
      res.writeHead(302, { Location: '/examples/web/index.html' });
      res.end();
      return;
    }
    if (!route) { res.writeHead(404); res.end('not found'); return; }
    const base = resolve(route[1]);
    const file = normalize(join(base, path.slice(route[0].length)));
    if (file !== base && !file.startsWith(base + sep)) { res.writeHead(403); res.end('outside'); return; }
    try {
      if (!(await stat(file)).isFile()) throw new Error('not a file');
      const body = await readFile(file);
      res.writeHead(200, { 'Content-Type': TYPES[extname(file)] || 'application/octet-stream', 'Cache-Control': 'no-store' });
      res.end(body);
    } catch {
      res.writeHead(404);
      res.end('not found');
    }
  });
  await new Promise((ok, fail) => { server.once('error', fail); server.listen(port, '127.0.0.1', ok); });
  const url = `http://127.0.0.1:${server.address().port}`;
  return { url, close: () => new Promise((ok) => server.close(ok)) };
}

if (import.meta.url === pathToFileURL(process.argv[1]).href) {
  const args = process.argv.slice(2);
  const option = (name) => { const i = args.indexOf(name); return i >= 0 ? args[i + 1] : undefined; };
  const settings = {};
  if (option('--port')) settings.port = Number(option('--port'));
  if (option('--package')) settings.packageDir = option('--package');
  if (option('--node-modules')) settings.nodeModules = option('--node-modules');
  if (option('--assets')) settings.assets = option('--assets');
  const { url } = await startServer(settings);
  console.log(`Marionette's three.js example: ${url}/examples/web/index.html`);
}
