#!/usr/bin/env bash
# Memory against data size: generates a BVH of about 100 MB with the shared peers'
# generator (node /work/shared/peers/gen_bvh.mjs, beside the checkout) in a scratch folder, imports
# it with bvh.import and reports the peak RSS beside the size of the decoded motion. A reader that
# holds the file, or a per-frame structure, shows as RSS well above the motion's size.
# `make bench-memory [BENCH_FRAMES=N]`; prints one RESULT line.
set -u
build="${RF_BUILDDIR:?}"
src="${RF_SRCDIR:?}"
frames=${BENCH_FRAMES:-108100} # 100 MiB in the generator's number format
gen="$src/../shared/peers/gen_bvh.mjs"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
command -v node >/dev/null && [ -f "$gen" ] || { echo "# skipped: needs node and $gen"; exit 77; }
node "$gen" "$frames" 120 "$tmp/big.bvh" >/dev/null || exit 1
cat >"$tmp/p.json" <<JSON
{"format": "rigflow.pipeline", "version": 1, "nodes": [
  {"id": "source", "type": "bvh.import", "params": {"path": "$tmp/big.bvh"}},
  {"id": "summary", "type": "report.summary",
   "inputs": {"skeleton": "source.skeleton", "animation": "source.animation"}}]}
JSON
# GNU time's %M is the peak resident set in KiB; the libtool wrapper execs the real binary.
/usr/bin/time -f '%M %e' -o "$tmp/time" "$build/rigflow" --quiet run "$tmp/p.json" >"$tmp/out" || exit 1
read -r rss_kb secs <"$tmp/time"
bytes=$(stat -c %s "$tmp/big.bvh")
joints=31
motion=$((frames * joints * 7 * 4)) # float rotations (4) and translations (3) per joint-frame
echo "# $(cat "$tmp/out")"
printf 'RESULT {"bench": "bvh-import-memory", "file_mb": %.1f, "frames": %d, "motion_mb": %.1f, "peak_rss_mb": %.1f, "overhead_mb": %.1f, "seconds": %s}\n' \
    "$(echo "$bytes / 1048576" | bc -l)" "$frames" "$(echo "$motion / 1048576" | bc -l)" \
    "$(echo "$rss_kb / 1024" | bc -l)" "$(echo "($rss_kb * 1024 - $motion) / 1048576" | bc -l)" "$secs"
