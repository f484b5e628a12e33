// Runs Khronos' glTF validator on each .glb named on the command line and
// prints one line per file: "PASS|FAIL gltf_validator/NAME: E errors, W
// warnings, I infos, H hints" (the issues listed when there are errors or
// warnings). A file passes with no error and no warning.
import { readFile } from 'node:fs/promises';
import { basename } from 'node:path';
import validator from 'gltf-validator';

let failed = 0;
for (const path of process.argv.slice(2)) {
    const name = basename(path);
    let report;
    try {
        const bytes = new Uint8Array(await readFile(path));
        report = await validator.validateBytes(bytes, { uri: name, maxIssues: 50 });
    } catch (err) {
        console.log(`FAIL gltf_validator/${name}: the validator could not read it: ${err}`);
        failed++;
        continue;
    }
    const n = report.issues;
    const line = `${n.numErrors} errors, ${n.numWarnings} warnings, ${n.numInfos} infos, ${n.numHints} hints`;
    if (n.numErrors || n.numWarnings) {
        failed++;
        const what = n.messages.filter((m) => m.severity <= 1).map((m) => `${m.code} ${m.pointer || ''} ${m.message}`);
        console.log(`FAIL gltf_validator/${name}: ${line}: ${what.slice(0, 5).join(' | ')}`);
    } else {
        const info = n.messages.map((m) => m.code);
        console.log(`PASS gltf_validator/${name}`);
        console.log(`INFO gltf_validator/${name}: ${line}${info.length ? ' (' + [...new Set(info)].join(', ') + ')' : ''}; ` +
            `${report.info.totalVertexCount} vertices, ${report.info.totalTriangleCount} triangles, generator "${report.info.generator}"`);
    }
}
process.exit(failed ? 1 : 0);
