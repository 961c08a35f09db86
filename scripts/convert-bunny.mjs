#!/usr/bin/env node
// Converts the Stanford bunny from the npm package `bunny` (1.0.1, public domain) into the
// Wavefront OBJ that sdfgen bundles as its default model (assets/bunny.obj).
//
// Usage, from a scratch directory outside the repository:
//   npm pack bunny@1.0.1 && tar xzf bunny-1.0.1.tgz
//   node /path/to/sdfgen/scripts/convert-bunny.mjs package /path/to/sdfgen/assets/bunny.obj
//
// The package's index.js is CommonJS exporting `positions` (an array of [x, y, z]) and `cells`
// (an array of 0-based vertex index triples). The OBJ gets a one-line header comment, one `v` line
// per position and one `f` line per cell, with 1-based indices.
//
// Winding: sdfgen wants faces counter-clockwise seen from outside, i.e. outward normals, which
// makes the signed volume sum of det(a, b, c) / 6 over all triangles positive. The bunny 1.0.1 data
// already winds that way (signed volume about +194.3), so nothing is flipped; the script still
// checks, and flips every triangle should the input ever wind the other way, saying so on stderr.
// It also reports boundary edges (edges used by only one triangle): zero means the mesh is closed.

import { createRequire } from "node:module";
import { writeFileSync, statSync } from "node:fs";
import path from "node:path";

function fail(message) {
  console.error(`convert-bunny: ${message}`);
  process.exit(1);
}

const [input, output] = process.argv.slice(2);
if (!input || !output) fail("usage: node convert-bunny.mjs <bunny package directory or index.js> <output.obj>");

const indexJs = statSync(input).isDirectory() ? path.join(input, "index.js") : input;
const packageJson = path.join(path.dirname(indexJs), "package.json");
const require = createRequire(import.meta.url);
const { positions, cells } = require(path.resolve(indexJs));
let version = "unknown";
try { version = require(path.resolve(packageJson)).version; } catch { /* no package.json beside it */ }

if (!Array.isArray(positions) || !Array.isArray(cells)) fail(`${indexJs} does not export positions and cells`);
for (const p of positions) {
  if (!Array.isArray(p) || p.length !== 3 || !p.every(Number.isFinite)) fail(`bad position ${JSON.stringify(p)}`);
}
for (const c of cells) {
  if (!Array.isArray(c) || c.length !== 3 || !c.every((i) => Number.isInteger(i) && i >= 0 && i < positions.length)) {
    fail(`bad cell ${JSON.stringify(c)}`);
  }
}

function signedVolume(tris) {
  let sum = 0;
  for (const [ia, ib, ic] of tris) {
    const [ax, ay, az] = positions[ia], [bx, by, bz] = positions[ib], [cx, cy, cz] = positions[ic];
    sum += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
  }
  return sum / 6;
}

let triangles = cells.map((c) => [...c]);
let volume = signedVolume(triangles);
if (volume < 0) {
  console.error("convert-bunny: input winds clockwise seen from outside; flipping every triangle");
  triangles = triangles.map(([a, b, c]) => [a, c, b]);
  volume = -volume;
}

// Undirected edge use counts: 1 = boundary edge, 2 = interior edge of a closed surface, more = non-manifold.
const edgeUses = new Map();
for (const t of triangles) {
  for (let k = 0; k < 3; ++k) {
    const u = t[k], w = t[(k + 1) % 3];
    const key = u < w ? `${u},${w}` : `${w},${u}`;
    edgeUses.set(key, (edgeUses.get(key) ?? 0) + 1);
  }
}
let boundary = 0, nonManifold = 0;
for (const n of edgeUses.values()) {
  if (n === 1) ++boundary;
  else if (n > 2) ++nonManifold;
}

const lines = [`# Stanford bunny, converted from the npm package bunny ${version} (public domain) by scripts/convert-bunny.mjs`];
for (const [x, y, z] of positions) lines.push(`v ${x} ${y} ${z}`);
for (const [a, b, c] of triangles) lines.push(`f ${a + 1} ${b + 1} ${c + 1}`);
writeFileSync(output, lines.join("\n") + "\n");

console.error(
  `convert-bunny: wrote ${output}: ${positions.length} vertices, ${triangles.length} triangles, ` +
  `${edgeUses.size} edges (${boundary} boundary, ${nonManifold} non-manifold), signed volume ${volume.toFixed(6)}`);
