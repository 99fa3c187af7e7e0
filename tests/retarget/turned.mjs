// Helper of test_retarget_turned.sh.
//   node turned.mjs pipeline IN OUT: writes OUT, the pipeline IN with a `transform` node ("move",
//     its turn set with -p move.turn=DEG) between the target's import and everything reading the
//     target's skeleton or mesh; the target's own clip (reference) is left out, its root keys
//     unturned.
//   node turned.mjs compare BASE.json TURNED.json LABEL: exit 1 unless the measures of the two
//     runs (retarget.measure's JSON) are the same: direction fidelity, foot skate and ground
//     within 1e-3 (degrees, legs per second, legs), the mesh's floor, stretch and torn seams
//     within 1e-3 % of the height, on as many edges and seams.
import { readFileSync, writeFileSync } from "node:fs";

const [mode, a, b, label] = process.argv.slice(2);

if (mode === "pipeline") {
    const p = JSON.parse(readFileSync(a, "utf8"));
    const swap = (v) =>
        v === "target.skeleton" ? "move.skeleton" : v === "target.mesh" ? "move.mesh" : v;
    for (const n of p.nodes) {
        if (!n.inputs)
            continue;
        delete n.inputs.reference;
        for (const [k, v] of Object.entries(n.inputs))
            n.inputs[k] = Array.isArray(v) ? v.map(swap) : swap(v);
    }
    const at = p.nodes.findIndex((n) => n.id === "target") + 1;
    p.nodes.splice(at, 0, {
        id: "move",
        type: "transform",
        inputs: { skeleton: "target.skeleton", mesh: "target.mesh" },
    });
    writeFileSync(b, JSON.stringify(p, null, 2));
    process.exit(0);
}

const base = JSON.parse(readFileSync(a, "utf8"));
const turned = JSON.parse(readFileSync(b, "utf8"));
const pct = (x) => (x == null ? x : 100 * x);
const figures = [
    ["fidelity_mean_deg", (m) => m.fidelity_mean_deg, 1e-3],
    ["skate_target", (m) => m.skate_target, 1e-3],
    ["ground_error", (m) => m.ground_error, 1e-3],
    ["floor_median %", (m) => pct(m.mesh?.floor_median), 1e-3],
    ["floor_p95 %", (m) => pct(m.mesh?.floor_p95), 1e-3],
    ["parts_below %", (m) => pct(m.mesh?.parts_below), 1e-3],
    ["stretch_p99 %", (m) => pct(m.mesh?.stretch_p99), 1e-3],
    ["part_stretch_p99 %", (m) => pct(m.mesh?.part_stretch_p99), 1e-3],
    ["seam_p99 %", (m) => pct(m.mesh?.seam_p99), 1e-3],
    ["edges", (m) => m.mesh?.edges, 0],
    ["seams", (m) => m.mesh?.seams, 0],
];
let bad = false;
const line = [];
for (const [name, get, tol] of figures) {
    const x = get(base), y = get(turned);
    const same = (x == null && y == null) || Math.abs(x - y) <= tol;
    if (!same)
        bad = true;
    line.push(`${name} ${y} (${x})${same ? "" : " DIFFERS"}`);
}
console.log(`${label}: ${line.join(", ")}`);
process.exit(bad ? 1 : 0);
