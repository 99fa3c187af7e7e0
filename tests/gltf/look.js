// What a GLB carries besides its skeleton, read from the file itself (not through rigflow), for
// the export tests:
//   node look.js counts FILE.glb        prints "materials=M images=I uvsets=U animations=A
//                                       skins=S meshes=N", one "animation NAME DURATION" line per
//                                       clip, one "morph NAME WEIGHT LARGEST-DISPLACEMENT" per target,
//                                       one "mesh NAME VERTICES" per mesh
//   node look.js same A.glb B.glb       exit 1 unless B has A's images (same bytes, same order) and
//                                       A's materials (every factor, texture slot and flag, glTF
//                                       defaults applied; images compared by content)
//   node look.js three FILE.glb...      loads each with three.js's GLTFLoader; exit 1 when one
//                                       fails or loses a material's texture, 77 without 'three'
//   node look.js stand FILE.glb         prints "median M p5 P" of the frames' lowest skin joint
//                                       over the rest's lowest (what a viewer or a contact sheet
//                                       takes as the floor), in fractions of the rest's height
// The npm package is looked up as validate.js does ($RF_NPM_DIR, $RF_BUILDDIR/npm/node_modules).
'use strict';
const fs = require('fs');
const path = require('path');
const crypto = require('crypto');

function readGlb(file) {
    const b = fs.readFileSync(file);
    if (b.readUInt32LE(0) !== 0x46546c67) throw new Error(`${file}: not a GLB`);
    const jsonLen = b.readUInt32LE(12);
    const json = JSON.parse(b.subarray(20, 20 + jsonLen).toString('utf8'));
    let bin = null;
    if (20 + jsonLen + 8 <= b.length) {
        const binLen = b.readUInt32LE(20 + jsonLen);
        bin = b.subarray(28 + jsonLen, 28 + jsonLen + binLen);
    }
    return { json, bin, bytes: b };
}

function imageBytes(g, i) {
    const im = g.json.images[i];
    if (im.bufferView === undefined) return Buffer.alloc(0);
    const v = g.json.bufferViews[im.bufferView];
    return g.bin.subarray(v.byteOffset || 0, (v.byteOffset || 0) + v.byteLength);
}

// The float values of an accessor (tightly packed or strided), or null.
function floats(g, index) {
    if (index === undefined) return null;
    const acc = g.json.accessors[index];
    if (acc.componentType !== 5126 || acc.bufferView === undefined) return null;
    const v = g.json.bufferViews[acc.bufferView];
    const n = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4 }[acc.type];
    const stride = v.byteStride || n * 4;
    const base = (v.byteOffset || 0) + (acc.byteOffset || 0);
    const out = new Float32Array(acc.count * n);
    for (let i = 0; i < acc.count; i++)
        for (let c = 0; c < n; c++) out[i * n + c] = g.bin.readFloatLE(base + i * stride + c * 4);
    return out;
}

function animationDuration(g, a) {
    let d = 0;
    for (const s of a.samplers) d = Math.max(d, g.json.accessors[s.input].max[0]);
    return d;
}

function counts(file) {
    const g = readGlb(file);
    const j = g.json;
    let uv = 0;
    for (const m of j.meshes || [])
        for (const p of m.primitives)
            for (const k of Object.keys(p.attributes))
                if (k.startsWith('TEXCOORD_')) uv = Math.max(uv, parseInt(k.slice(9), 10) + 1);
    const n = (k) => (j[k] || []).length;
    console.log(`materials=${n('materials')} images=${n('images')} uvsets=${uv} ` +
                `animations=${n('animations')} skins=${n('skins')} meshes=${n('meshes')}`);
    for (const a of j.animations || [])
        console.log(`animation ${a.name} ${animationDuration(g, a).toFixed(3)}`);
    for (const m of j.meshes || [])
        console.log(`mesh ${m.name} ${m.primitives.reduce((v, p) => v + j.accessors[p.attributes.POSITION].count, 0)}`);
    // morph targets: name, rest weight, the largest displacement over every primitive
    for (const m of j.meshes || []) {
        const names = (m.extras && m.extras.targetNames) || [];
        const count = m.primitives.length ? (m.primitives[0].targets || []).length : 0;
        for (let t = 0; t < count; t++) {
            let most = 0;
            for (const p of m.primitives) {
                const v = p.targets && p.targets[t] ? floats(g, p.targets[t].POSITION) : null;
                for (const x of v || []) most = Math.max(most, Math.abs(x));
            }
            console.log(`morph ${names[t] || t} ${((m.weights || [])[t] || 0).toFixed(3)} ${most.toFixed(3)}`);
        }
    }
}

// A material as a reader sees it: glTF defaults filled in, textures by image content.
function materialView(g, m) {
    const pbr = m.pbrMetallicRoughness || {};
    const tex = (t) => {
        if (!t) return null;
        const src = g.json.textures[t.index].source;
        const hash = crypto.createHash('sha256').update(imageBytes(g, src)).digest('hex');
        return { image: hash, texCoord: t.texCoord || 0, scale: t.scale === undefined ? 1 : t.scale,
                 strength: t.strength === undefined ? 1 : t.strength };
    };
    const f = (v) => Math.fround(v);
    return {
        name: m.name || '',
        baseColorFactor: (pbr.baseColorFactor || [1, 1, 1, 1]).map(f),
        metallicFactor: f(pbr.metallicFactor === undefined ? 1 : pbr.metallicFactor),
        roughnessFactor: f(pbr.roughnessFactor === undefined ? 1 : pbr.roughnessFactor),
        baseColorTexture: tex(pbr.baseColorTexture),
        metallicRoughnessTexture: tex(pbr.metallicRoughnessTexture),
        normalTexture: tex(m.normalTexture),
        occlusionTexture: tex(m.occlusionTexture),
        emissiveTexture: tex(m.emissiveTexture),
        emissiveFactor: (m.emissiveFactor || [0, 0, 0]).map(f),
        alphaMode: m.alphaMode || 'OPAQUE',
        alphaCutoff: (m.alphaMode === 'MASK') ? f(m.alphaCutoff === undefined ? 0.5 : m.alphaCutoff) : null,
        doubleSided: !!m.doubleSided,
    };
}

function same(fa, fb) {
    const a = readGlb(fa), b = readGlb(fb);
    const problems = [];
    const ia = (a.json.images || []).map((_, i) => imageBytes(a, i));
    const ib = (b.json.images || []).map((_, i) => imageBytes(b, i));
    if (ia.length !== ib.length) problems.push(`images: ${ia.length} in ${fa}, ${ib.length} in ${fb}`);
    for (let i = 0; i < Math.min(ia.length, ib.length); i++)
        if (!ia[i].equals(ib[i])) problems.push(`image ${i}: bytes differ`);
    const ma = (a.json.materials || []).map((m) => materialView(a, m));
    const mb = (b.json.materials || []).map((m) => materialView(b, m));
    if (ma.length !== mb.length) problems.push(`materials: ${ma.length} in ${fa}, ${mb.length} in ${fb}`);
    for (let i = 0; i < Math.min(ma.length, mb.length); i++) {
        const x = JSON.stringify(ma[i]), y = JSON.stringify(mb[i]);
        if (x !== y) problems.push(`material ${i}:\n  ${x}\n  ${y}`);
    }
    // Texture coordinates, primitive by primitive where both files have the same primitives
    // (a single-mesh source keeps its vertex order through rigflow): equal to 1e-6.
    const pa = (a.json.meshes || []).flatMap((m) => m.primitives);
    const pb = (b.json.meshes || []).flatMap((m) => m.primitives);
    let uvCompared = 0;
    if (pa.length === pb.length)
        for (let i = 0; i < pa.length; i++) {
            const ua = floats(a, pa[i].attributes.TEXCOORD_0), ub = floats(b, pb[i].attributes.TEXCOORD_0);
            if (!ua || !ub || ua.length !== ub.length) continue;
            let worst = 0;
            for (let k = 0; k < ua.length; k++) worst = Math.max(worst, Math.abs(ua[k] - ub[k]));
            if (worst > 1e-6) problems.push(`primitive ${i}: TEXCOORD_0 differs by up to ${worst}`);
            uvCompared++;
        }
    for (const p of problems) console.log(`${fb}: ${p}`);
    console.log(`${fb}: ${ia.length} images, ${ma.length} materials, ${uvCompared} primitives' ` +
                `texture coordinates compared, ${problems.length} differences`);
    return problems.length ? 1 : 0;
}

function npmDir(pkg) {
    const dirs = [];
    if (process.env.RF_NPM_DIR) dirs.push(path.join(process.env.RF_NPM_DIR, pkg));
    if (process.env.RF_BUILDDIR)
        dirs.push(path.join(process.env.RF_BUILDDIR, 'npm', 'node_modules', pkg));
    for (const d of dirs) if (fs.existsSync(path.join(d, 'package.json'))) return d;
    return null;
}

// Node has no image decoder: createImageBitmap stands in, accepting only bytes that are a PNG
// (its size from the IHDR chunk) or a JPEG, so an image three.js hands over must be one.
function installImageStub() {
    globalThis.self = globalThis;
    globalThis.createImageBitmap = async (blob) => {
        const b = Buffer.from(await blob.arrayBuffer());
        const png = b.length > 24 && b.readUInt32BE(0) === 0x89504e47;
        const jpeg = b.length > 3 && b[0] === 0xff && b[1] === 0xd8 && b[2] === 0xff;
        if (!png && !jpeg) throw new Error('image bytes are neither PNG nor JPEG');
        return { width: png ? b.readUInt32BE(16) : 1, height: png ? b.readUInt32BE(20) : 1, close() {} };
    };
}

async function three(files) {
    const dir = npmDir('three');
    if (!dir) {
        console.log("three not found (set RF_NPM_DIR or run ./quickstart.sh deps): skipped");
        return 77;
    }
    installImageStub();
    const url = require('url');
    const { GLTFLoader } = await import(url.pathToFileURL(path.join(dir, 'examples/jsm/loaders/GLTFLoader.js')).href);
    let failed = 0;
    for (const file of files) {
        const g = readGlb(file);
        const buf = g.bytes.buffer.slice(g.bytes.byteOffset, g.bytes.byteOffset + g.bytes.length);
        try {
            const gltf = await new Promise((ok, ko) => new GLTFLoader().parse(buf, '', ok, ko));
            let meshes = 0, maps = 0, bones = 0;
            gltf.scene.traverse((o) => {
                if (o.isMesh) {
                    meshes++;
                    for (const m of [].concat(o.material)) if (m.map && m.map.image && m.map.image.width) maps++;
                }
                if (o.isBone) bones++;
            });
            const wantMaps = (g.json.meshes || []).reduce((n, m) => n + m.primitives.filter((p) =>
                p.material !== undefined && ((g.json.materials[p.material].pbrMetallicRoughness || {}).baseColorTexture)).length, 0);
            const wantBones = (g.json.skins || []).reduce((n, s) => n + s.joints.length, 0) ? (g.json.skins[0].joints.length) : 0;
            const ok = maps === wantMaps && gltf.animations.length === (g.json.animations || []).length && bones >= wantBones;
            console.log(`${file}: ${meshes} meshes, ${maps}/${wantMaps} textured, ${bones} bones, ` +
                        `${gltf.animations.length} clips${ok ? '' : ': MISMATCH'}`);
            if (!ok) failed++;
        } catch (e) {
            console.log(`${file}: GLTFLoader failed: ${e && e.message ? e.message : e}`);
            failed++;
        }
    }
    return failed ? 1 : 0;
}

// Rotates v by the unit quaternion q (x, y, z, w).
function qRotate(q, v) {
    const [x, y, z, w] = q;
    const tx = 2 * (y * v[2] - z * v[1]), ty = 2 * (z * v[0] - x * v[2]), tz = 2 * (x * v[1] - y * v[0]);
    return [v[0] + w * tx + (y * tz - z * ty), v[1] + w * ty + (z * tx - x * tz), v[2] + w * tz + (x * ty - y * tx)];
}

function qMul(a, b) {
    return [a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1], a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
            a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3], a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]];
}

// Heights (y) of the first skin's joints with each node's translation and rotation given by
// `local(i)` (scale left out: the exports write none).
function jointHeights(g, local) {
    const nodes = g.json.nodes, parent = new Map(), world = new Map();
    nodes.forEach((n, i) => (n.children || []).forEach((c) => parent.set(c, i)));
    const at = (i) => {
        if (world.has(i)) return world.get(i);
        const [t, r] = local(i);
        let w = { t: t.slice(), r: r.slice() };
        if (parent.has(i)) {
            const p = at(parent.get(i)), d = qRotate(p.r, t);
            w = { t: [p.t[0] + d[0], p.t[1] + d[1], p.t[2] + d[2]], r: qMul(p.r, r) };
        }
        world.set(i, w);
        return w;
    };
    return g.json.skins[0].joints.map((j) => at(j).t[1]);
}

// How the animated joints stand over the rest's floor: the first clip's every key time.
function stand(file) {
    const g = readGlb(file), nodes = g.json.nodes;
    const rest = (i) => [nodes[i].translation || [0, 0, 0], nodes[i].rotation || [0, 0, 0, 1]];
    const restY = jointHeights(g, rest), floor = Math.min(...restY);
    const height = Math.max(...restY) - floor;
    const keyed = new Map(), a = g.json.animations[0];
    let frames = 0;
    for (const c of a.channels) {
        const v = floats(g, a.samplers[c.sampler].output), n = c.target.path === 'rotation' ? 4 : 3;
        if (c.target.path === 'scale') continue;
        keyed.set(`${c.target.node} ${c.target.path}`, { v, n });
        frames = Math.max(frames, v.length / n);
    }
    const key = (i, p, f, dflt) => {
        const k = keyed.get(`${i} ${p}`);
        if (!k) return dflt;
        const at = Math.min(f, k.v.length / k.n - 1) * k.n;
        return Array.from(k.v.subarray(at, at + k.n));
    };
    const lows = [];
    for (let f = 0; f < frames; f++) {
        const y = jointHeights(g, (i) => [key(i, 'translation', f, rest(i)[0]), key(i, 'rotation', f, rest(i)[1])]);
        lows.push((Math.min(...y) - floor) / height);
    }
    lows.sort((p, q) => p - q);
    const q = (x) => lows[Math.floor(x * (lows.length - 1))];
    console.log(`median ${q(0.5).toFixed(4)} p5 ${q(0.05).toFixed(4)}`);
    return 0;
}

async function main() {
    const [cmd, ...args] = process.argv.slice(2);
    if (cmd === 'counts') return args.forEach(counts), 0;
    if (cmd === 'same') return same(args[0], args[1]);
    if (cmd === 'three') return three(args);
    if (cmd === 'stand') return stand(args[0]);
    console.log('usage: look.js counts|same|three|stand FILE...');
    return 2;
}

main().then((code) => process.exit(code || 0), (e) => {
    console.log(`look.js: ${e && e.stack ? e.stack : e}`);
    process.exit(1);
});
