#!/bin/sh
# Every source clip of the shared data (CMU, the Bandai walk, kick and run, the Fox's Survey,
# Walk and Run) onto every rigged model there, through pipelines/retarget.json with its
# matcher, measured on the skinned mesh beside each model's own clip (tests/retarget/sweep.mjs
# judges and prints the table that doc/retargeting.md shows). Skips without ../shared/data, the
# skeletal-similarity matcher or node.
rigflow="${RF_BUILDDIR:-.}/rigflow"
pipeline="${RF_SRCDIR:-.}/pipelines/retarget.json"
judge="${RF_SRCDIR:-.}/tests/retarget/sweep.mjs"
data="${RF_DATA_DIR:-}"
node="${RF_NODE:-node}"
if [ ! -f "$data/bvh/cmu_01_01.bvh" ]; then
    echo "RF_DATA_DIR not found (../shared/data): skipped"
    exit 77
fi
if ! "$node" --version >/dev/null 2>&1; then
    echo "node not found: skipped"
    exit 77
fi
if ! "$rigflow" describe skeletal-similarity >/dev/null 2>&1; then
    echo "the skeletal-similarity matcher is not installed: skipped"
    exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
sources="bvh/cmu_01_01.bvh bvh/bandai_walk.bvh bvh/bandai_kick.bvh bvh/bandai_run.bvh
models/Fox.glb@Survey models/Fox.glb@Walk models/Fox.glb@Run"
targets="models/RobotExpressive.glb models/Wizard.glb models/girl.glb models/greenman.glb
models/RiggedFigure.glb models/BCN_Epileptic.X models/Testwuson.X models/huesitos.fbx
models/animation_with_skeleton.fbx models/simple_skin.gltf models/ogre/ninja.mesh
models/Fox.glb models/vrm_sample.glb models/creatures/animala_horse.b3d
models/creatures/animalia_wolf.b3d models/creatures/animalia_cat.b3d
models/creatures/animalia_fox.b3d models/creatures/animalia_bat.b3d
models/creatures/animalia_bird.b3d models/creatures/animalia_owl.b3d
models/creatures/animalia_bull_frog.b3d models/creatures/draconis_fire_dragon.b3d
models/creatures/draconis_jungle_wyvern.b3d"
for s in $sources; do
    clip=${s#*@}
    file=${s%@*}
    sname=$(basename "$file" | sed 's/\.[^.]*$//')
    [ "$clip" = "$s" ] && clip="" || sname="$sname-$clip"
    for t in $targets; do
        tname=$(basename "$t" | sed 's/\.[^.]*$//')
        name="${sname}__${tname}"
        set -- -p "source.path=$data/$file" -p "target.path=$data/$t" \
            -p "export.path=$tmp/out.glb" -p "measure.path=$tmp/$name.json"
        [ -n "$clip" ] && set -- "$@" -p "source.clip=$clip"
        "$rigflow" -q run "$pipeline" "$@" >"$tmp/$name.log" 2>&1
        rc=$?
        echo "$rc" >"$tmp/$name.rc"
        [ "$rc" = 0 ] || { echo "FAIL: $name (exit $rc)"; tail -n 3 "$tmp/$name.log"; }
    done
done
"$node" "$judge" "$tmp"
