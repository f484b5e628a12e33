// Reads a patchwork .glb back and compares it with the OBJ the same command
// wrote: the same triangles (the OBJ's faces fan-triangulated, in any
// order), each with the same three corner positions and texture
// coordinates, bit for bit (glTF's v is 1 - OBJ's v), and every normal is
// unit length.
// Usage: node roundtrip.mjs NAME.glb NAME.obj  ->  "PASS|FAIL gltf_roundtrip/NAME: ..."
import { readFile } from 'node:fs/promises';
import { basename } from 'node:path';

function parseGlb(buf) {
    if (buf.toString('latin1', 0, 4) !== 'glTF' || buf.readUInt32LE(4) !== 2) throw new Error('not GLB version 2');
    if (buf.readUInt32LE(8) !== buf.length) throw new Error(`header length ${buf.readUInt32LE(8)}, file ${buf.length}`);
    const jlen = buf.readUInt32LE(12);
    if (buf.toString('latin1', 16, 20) !== 'JSON' || jlen % 4) throw new Error('bad JSON chunk');
    const json = JSON.parse(buf.toString('utf8', 20, 20 + jlen));
    const b0 = 20 + jlen, blen = buf.readUInt32LE(b0);
    if (buf.toString('latin1', b0 + 4, b0 + 8) !== 'BIN\0' || blen % 4 || b0 + 8 + blen !== buf.length) throw new Error('bad BIN chunk');
    const bin = buf.subarray(b0 + 8, b0 + 8 + blen);
    const read = (i) => {
        const a = json.accessors[i], v = json.bufferViews[a.bufferView];
        const n = a.count * { SCALAR: 1, VEC2: 2, VEC3: 3 }[a.type];
        const ab = bin.buffer.slice(bin.byteOffset + v.byteOffset, bin.byteOffset + v.byteOffset + v.byteLength);
        return a.componentType === 5125 ? new Uint32Array(ab, 0, n) : new Float32Array(ab, 0, n);
    };
    return { json, read };
}

function parseObj(text) {
    const v = [], vt = [], tris = [];
    for (const line of text.split('\n')) {
        const w = line.trim().split(/\s+/);
        if (w[0] === 'v') v.push(w.slice(1, 4).map(Number));
        else if (w[0] === 'vt') vt.push(w.slice(1, 3).map(Number));
        else if (w[0] === 'f') {
            const c = w.slice(1).map((s) => s.split('/').map((x) => +x - 1));
            for (let i = 1; i + 1 < c.length; i++) tris.push([c[0], c[i], c[i + 1]]);
        }
    }
    return { v, vt, tris };
}

const [glbPath, objPath] = process.argv.slice(2);
const name = basename(glbPath, '.glb');
try {
    const { json, read } = parseGlb(await readFile(glbPath));
    const obj = parseObj(await readFile(objPath, 'utf8'));
    const prim = json.meshes[0].primitives[0];
    const idx = read(prim.indices), pos = read(prim.attributes.POSITION), nrm = read(prim.attributes.NORMAL);
    const uv = read(prim.attributes.TEXCOORD_0);
    if (idx.length !== 3 * obj.tris.length) throw new Error(`${idx.length / 3} triangles, the OBJ has ${obj.tris.length}`);
    // each triangle as its three corners (position, coordinate), both files'
    // in float32 (the OBJ's v as glTF's 1 - v); compared as sorted lists, so
    // that an OBJ may order its faces differently (pgp's groups them)
    const glbTris = [], objTris = [];
    for (let t = 0; t < obj.tris.length; t++) {
        const a = [], b = [];
        for (let k = 0; k < 3; k++) {
            const g = idx[3 * t + k], [pv, pt] = obj.tris[t][k];
            a.push(pos[3 * g], pos[3 * g + 1], pos[3 * g + 2], uv[2 * g], uv[2 * g + 1]);
            b.push(...obj.v[pv].map(Math.fround), Math.fround(obj.vt[pt][0]), Math.fround(1 - Math.fround(obj.vt[pt][1])));
        }
        glbTris.push(a.join(' '));
        objTris.push(b.join(' '));
    }
    glbTris.sort();
    objTris.sort();
    let bad = 0;
    for (let t = 0; t < glbTris.length; t++) if (glbTris[t] !== objTris[t]) bad++;
    let worst = 0;
    for (let i = 0; i < nrm.length; i += 3) worst = Math.max(worst, Math.abs(Math.hypot(nrm[i], nrm[i + 1], nrm[i + 2]) - 1));
    if (bad || worst > 1e-6) console.log(`FAIL gltf_roundtrip/${name}: ${bad} triangles differ from the OBJ's; normals off unit length by ${worst}`);
    else {
        console.log(`PASS gltf_roundtrip/${name}`);
        console.log(`INFO gltf_roundtrip/${name}: ${obj.tris.length} triangles, ${pos.length / 3} vertices (${obj.v.length} in the OBJ, split at seams), positions and coordinates bit for bit`);
    }
} catch (err) {
    console.log(`FAIL gltf_roundtrip/${name}: ${err.message}`);
}
