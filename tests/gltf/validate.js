// Runs the Khronos glTF-Validator (npm package gltf-validator) on each file given and prints its
// errors and warnings. Exit status: 0 when no file has an error, 1 when one has, 77 (automake's
// "skip") when the package cannot be found. The package is looked up in $RF_NPM_DIR (a
// node_modules folder), then in $RF_BUILDDIR/npm/node_modules (where ./quickstart.sh deps installs
// it), then on node's usual paths.
'use strict';
const fs = require('fs');
const path = require('path');

function loadValidator() {
    const dirs = [];
    if (process.env.RF_NPM_DIR) dirs.push(path.join(process.env.RF_NPM_DIR, 'gltf-validator'));
    // where ./quickstart.sh deps installs npm tools: BUILDDIR/npm/node_modules
    if (process.env.RF_BUILDDIR)
        dirs.push(path.join(process.env.RF_BUILDDIR, 'npm', 'node_modules', 'gltf-validator'));
    dirs.push('gltf-validator');
    for (const d of dirs) {
        try {
            return require(d);
        } catch (e) { /* try the next place */ }
    }
    return null;
}

async function main() {
    const validator = loadValidator();
    if (!validator) {
        console.log('gltf-validator not found (set RF_NPM_DIR or run ./quickstart.sh deps): skipped');
        process.exit(77);
    }
    let failed = false;
    for (const file of process.argv.slice(2)) {
        const report = await validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
            uri: path.basename(file),
            maxIssues: 50,
        });
        const is = report.issues;
        console.log(`${file}: ${is.numErrors} errors, ${is.numWarnings} warnings, ` +
                    `${is.numInfos} infos, ${is.numHints} hints`);
        for (const m of is.messages)
            if (m.severity <= 1)
                console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code} ` +
                            `${m.pointer || ''}: ${m.message}`);
        if (is.numErrors > 0) failed = true;
    }
    process.exit(failed ? 1 : 0);
}

main().catch((e) => {
    console.log(`validator failed: ${e && e.message ? e.message : e}`);
    process.exit(1);
});
