// The browser's SH evaluation (web/src/sh.js) against the reference tables the C++ basis is tested with
// (tests/sh/data: mpmath at 40 digits and Boost at 1000 bits, complex Y_l^m with the Condon-Shortley phase).
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

import { complexY, evaluateSurface, invariants, shCount } from '../src/sh.js';

const dataDir = join(dirname(fileURLToPath(import.meta.url)), '..', '..', 'tests', 'sh', 'data');

function rows(file, columns) {
  return readFileSync(join(dataDir, file), 'utf8').split('\n')
    .filter((line) => line && !line.startsWith('#') && !/^[a-z]/i.test(line))
    .map((line) => line.split(',').slice(0, columns).map(Number));
}

function checkTable(file) {
  const table = rows(file, 6);
  assert.ok(table.length > 100, `${file}: ${table.length} rows`);
  let worst = 0;
  for (const [l, m, theta, phi, re, im] of table) {
    const [yre, yim] = complexY(l, m, theta, phi);
    // 1e-10 relative, 1e-14 absolute (cos(pi/2) is 6e-17 in double, the reference's exact zero is 1e-44).
    const diff = Math.hypot(yre - re, yim - im), bound = 1e-10 * Math.hypot(re, im) + 1e-14;
    worst = Math.max(worst, diff / bound);
    assert.ok(diff <= bound, `${file}: Y_${l}^${m}(${theta}, ${phi}) = ${yre} ${yim}i, reference ${re} ${im}i`);
  }
  return worst;
}

test('complex Y_l^m matches mpmath (all m, both poles)', () => { checkTable('mpmath_sh_reference.csv'); });
test('complex Y_l^m matches Boost', () => { checkTable('boost_sh_reference.csv'); });

test('a unit sphere from its degree-1 coefficients: x_1(u) = u and xi(1) = 4 pi', () => {
  // x = sqrt(4 pi / 3) * (Y_1^{-1} - Y_1^1) / sqrt 2, y = i sqrt(4 pi / 3) (Y_1^{-1} + Y_1^1) / sqrt 2, z = sqrt(4 pi / 3) Y_1^0
  const k = shCount(3);
  const c = { x: [], y: [], z: [] };
  for (const axis of ['x', 'y', 'z']) for (let j = 0; j < k; ++j) c[axis].push([0, 0]);
  const s = Math.sqrt(4 * Math.PI / 3), r2 = Math.SQRT1_2;
  c.x[1] = [s * r2, 0]; c.x[3] = [-s * r2, 0];
  c.y[1] = [0, s * r2]; c.y[3] = [0, s * r2];
  c.z[2] = [s, 0];
  const points = [];
  for (let i = 0; i < 50; ++i) {
    const t = Math.acos(1 - 2 * ((i * 0.618034) % 1)), p = 2 * Math.PI * ((i * 0.4142136) % 1);
    points.push(Math.sin(t) * Math.cos(p), Math.sin(t) * Math.sin(p), Math.cos(t));
  }
  const x = evaluateSurface(c, Float64Array.from(points), 3);
  for (let i = 0; i < points.length; ++i) assert.ok(Math.abs(x[i] - points[i]) < 1e-13, `component ${i}`);
  const xi = invariants(c);
  assert.ok(Math.abs(xi[1] - 4 * Math.PI) < 1e-12);
  assert.equal(xi[2], 0);
  // Degree 0 keeps only the (zero) mean position.
  assert.ok(evaluateSurface(c, Float64Array.from(points), 0).every((v) => v === 0));
});
