// Builds the web page into a directory that `wish serve --web-dir` serves: the page's own ES modules (src/) and
// the files it imports from the npm packages of package-lock.json (installed with `npm ci`). No bundler is needed:
// the browser resolves "three" through the import map of index.html. Nothing is fetched at run time.
//   node web/build.mjs --out build/release/web/dist
import { cpSync, existsSync, mkdirSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const outIndex = process.argv.indexOf('--out');
if (outIndex < 0 || !process.argv[outIndex + 1]) {
  console.error('usage: node web/build.mjs --out DIR');
  process.exit(2);
}
const out = process.argv[outIndex + 1];
const modules = join(here, 'node_modules');

// What the page imports from npm packages: [package, file inside the package, destination under vendor/].
const vendored = [
  ['three', 'build/three.module.js', 'three/three.module.js'],
  ['three', 'examples/jsm/controls/OrbitControls.js', 'three/OrbitControls.js'],
  ['three', 'LICENSE', 'three/LICENSE'],
];

const lock = JSON.parse(readFileSync(join(here, 'package-lock.json'), 'utf8'));
for (const [pkg] of vendored) {
  const manifest = join(modules, pkg, 'package.json');
  if (!existsSync(manifest)) {
    console.error(`web/build.mjs: ${pkg} is not installed in web/node_modules; run \`npm ci\` in web/ ` +
                  '(scripts/install-deps.sh does)');
    process.exit(1);
  }
  const installed = JSON.parse(readFileSync(manifest, 'utf8')).version;
  const locked = lock.packages[`node_modules/${pkg}`]?.version;
  if (installed !== locked) {
    console.error(`web/build.mjs: web/node_modules/${pkg} is ${installed}, package-lock.json says ${locked}; run \`npm ci\``);
    process.exit(1);
  }
}

rmSync(out, { recursive: true, force: true });
mkdirSync(out, { recursive: true });
cpSync(join(here, 'src'), out, { recursive: true });
for (const [pkg, file, dest] of vendored) {
  const target = join(out, 'vendor', dest);
  mkdirSync(dirname(target), { recursive: true });
  cpSync(join(modules, pkg, file), target);
}
// The OrbitControls module imports 'three', resolved by the import map; record what was built from what.
writeFileSync(join(out, 'vendor', 'versions.json'),
              JSON.stringify(Object.fromEntries(vendored.map(([p]) => [p, lock.packages[`node_modules/${p}`].version])), null, 1));
console.log(`web page built into ${out}`);
