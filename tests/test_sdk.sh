#!/usr/bin/env bash
# The SDK for third parties: install into a staging folder, build the two example plugins there
# from copies of their folders with nothing but pkg-config and their own Makefiles, install them,
# check them, and run a pipeline that uses them with the staged rigflow.
set -u
build="${RF_BUILDDIR:?}"
src="${RF_SRCDIR:?}"
tmp=$(mktemp -d)
trap 'chmod -R u+w "$tmp"; rm -rf "$tmp"' EXIT
stage="$tmp/stage"
pass=0 fail=0
ok() { pass=$((pass + 1)); echo "ok - $1"; }
bad() { fail=$((fail + 1)); echo "not ok - $1"; [ -f "$tmp/log" ] && tail -20 "$tmp/log" | sed 's/^/    /'; }

if ${MAKE:-make} -C "$build" install DESTDIR="$stage" >"$tmp/log" 2>&1; then ok "make install into a staging folder"
else bad "make install into a staging folder"; echo "$pass passed, $fail failed"; exit 1; fi

prefix_dir=$(find "$stage" -name rigflow-plugin.pc -printf '%h\n' | head -1)
[ -n "$prefix_dir" ] && ok "rigflow-plugin.pc installed" || bad "rigflow-plugin.pc installed"
# --define-prefix: the staged .pc's prefix becomes the folder it was found in, as for a relocated
# install, so --cflags and pluginsdir point into the staging folder.
export PKG_CONFIG_PATH="$prefix_dir"
pkgconfig="pkg-config --define-prefix"
pluginsdir=$($pkgconfig --variable=pluginsdir rigflow-plugin)
[ -f "$pluginsdir/bvh.so" ] && ok "bundled plugins in pluginsdir" || bad "bundled plugins in pluginsdir ($pluginsdir)"
[ -n "$(find "$stage" -path '*/include/rigflow/plugin.h')" ] && ok "SDK headers installed" || bad "SDK headers installed"

for ex in smooth match-nearest; do
    cp -r "$src/sdk/examples/$ex" "$tmp/$ex" && chmod -R u+w "$tmp/$ex"
    if ${MAKE:-make} -C "$tmp/$ex" install PKG_CONFIG="$pkgconfig" >"$tmp/log" 2>&1; then ok "example $ex builds and installs out of tree"
    else bad "example $ex builds and installs out of tree"; fi
done

bin=$(find "$stage" -path '*/bin/rigflow' | head -1)
libdir=$(dirname "$prefix_dir")
export LD_LIBRARY_PATH="$libdir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" RIGFLOW_PLUGIN_PATH="$pluginsdir"
"$bin" plugin-check "$pluginsdir"/example-*.so >"$tmp/log" 2>&1 && ok "plugin-check passes the examples" || bad "plugin-check passes the examples"

bvh="${RF_DATA_DIR:-}/bvh/cmu_01_01.bvh"
[ -f "$bvh" ] || bvh=/usr/share/assimp/models/BVH/01_01.bvh
if [ ! -f "$bvh" ]; then echo "# skipped the pipeline: no sample BVH"; echo "$pass passed, $fail failed"; [ "$fail" = 0 ]; exit; fi
cat >"$tmp/p.json" <<JSON
{"format": "rigflow.pipeline", "version": 1, "nodes": [
  {"id": "source", "type": "bvh.import", "params": {"path": "$bvh"}},
  {"id": "smooth", "type": "example.smooth", "params": {"window": 7}, "inputs": {"animation": "source.animation"}},
  {"id": "map", "type": "example.match-nearest", "inputs": {"target": "source.skeleton", "sources": ["source.skeleton"]}},
  {"id": "export", "type": "bvh.export", "params": {"path": "smooth.bvh"}, "inputs": {"skeleton": "source.skeleton", "animation": "smooth.animation"}},
  {"id": "summary", "type": "report.summary", "inputs": {"mapping": "map.mapping", "animation": "smooth.animation"}}]}
JSON
if "$bin" run "$tmp/p.json" >"$tmp/out" 2>"$tmp/log"; then ok "pipeline with both examples runs"; else bad "pipeline with both examples runs"; fi
# mapping a skeleton onto itself must map every joint
grep -q "31 of 31 target joints mapped" "$tmp/out" && ok "the matcher maps a skeleton onto itself fully" || bad "self-mapping complete: $(cat "$tmp/out")"
[ -s "$tmp/smooth.bvh" ] && ok "smoothed clip written" || bad "smoothed clip written"
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
