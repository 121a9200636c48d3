// Copies the three.js files the page needs from node_modules (installed by `npm ci`, version
// pinned in package-lock.json) into vendor/, which is committed and embedded in the penalty
// binary at build time, so building needs no npm. Run `npm run vendor` after changing the pin;
// `npm run vendor -- --check` exits 1 when vendor/ differs from node_modules (used by the tests).
import { readFileSync, writeFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(dirname(fileURLToPath(import.meta.url)));
const three = join(here, 'node_modules', 'three');
const version = JSON.parse(readFileSync(join(three, 'package.json'), 'utf8')).version;
const files = {
  'three.module.min.js': readFileSync(join(three, 'build', 'three.module.min.js'), 'utf8'),
  // OrbitControls imports the bare name 'three'; the page has no import map, so point it at the file.
  'OrbitControls.js': readFileSync(join(three, 'examples', 'jsm', 'controls', 'OrbitControls.js'), 'utf8')
    .replace("from 'three';", "from './three.module.min.js';"),
  'THREE_LICENSE': `three.js ${version} (https://threejs.org), MIT licence:\n\n` + readFileSync(join(three, 'LICENSE'), 'utf8'),
};
const check = process.argv.includes('--check');
let differ = 0;
for (const [name, content] of Object.entries(files)) {
  const target = join(here, 'vendor', name);
  if (check) {
    let current = '';
    try { current = readFileSync(target, 'utf8'); } catch { /* missing */ }
    if (current !== content) { console.log(`vendor/${name} differs from node_modules (three ${version})`); differ++; }
  } else {
    writeFileSync(target, content);
    console.log(`vendor/${name} (three ${version}, ${content.length} bytes)`);
  }
}
if (check && differ === 0) console.log(`vendor/ matches three ${version}`);
process.exit(check && differ > 0 ? 1 : 0);
