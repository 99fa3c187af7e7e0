#!/usr/bin/env bash
# The plugin index: `rigflow run` and `validate` open only the plugins of their pipeline's node
# types once the index knows the files; listing commands still see every plugin; a changed file
# is opened again; an index that lies, or none, changes no answer.
# Which plugin files a process opens is read from glibc's loader (LD_DEBUG=files: "calling init").
set -u
rigflow="${RF_BUILDDIR:?}/rigflow"
fixtures="$RF_BUILDDIR/tests/fixtures/.libs"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
pass=0 fail=0
ok() { pass=$((pass + 1)); echo "ok - $1"; }
bad() { fail=$((fail + 1)); echo "not ok - $1"; [ -f "$tmp/err" ] && sed 's/^/    stderr: /' "$tmp/err" | head -20; }
check() { if eval "$1"; then ok "$2"; else bad "$2"; fi; }

if ! LD_DEBUG=files /bin/true 2>&1 | grep -q 'calling init'; then
    echo "SKIP: the loader does not report what it opens (LD_DEBUG=files, glibc): nothing tested"
    exit 77
fi

# A plugin folder: two fixture plugins that provide the test.* node types the pipeline uses under
# different ids (the second is refused as a duplicate), and the names matcher, which it never needs.
plugins="$tmp/plugins"
mkdir "$plugins"
cp "$fixtures/fx_good.so" "$plugins/a_good.so"
cp "$fixtures/fx_dup.so" "$plugins/b_dup.so"
cp "$RF_BUILDDIR/plugins/.libs/match-names.so" "$plugins/c_names.so" || exit 99
cat >"$tmp/p.json" <<'EOF'
{"format": "rigflow.pipeline", "version": 1,
 "nodes": [{"id": "s", "type": "test.source", "params": {"value": 7}},
           {"id": "w", "type": "test.sink", "params": {"path": "out.txt"}, "inputs": {"in": "s.value"}}]}
EOF
export RIGFLOW_PLUGIN_PATH="$plugins"
export RIGFLOW_PLUGIN_INDEX="$tmp/index"

# opened CMD...: the files of $RIGFLOW_PLUGIN_PATH the command opened (basenames), sorted
opened() {
    LD_DEBUG=files "$@" 2>"$tmp/ld" >"$tmp/out"
    local code=$?
    grep -o "calling init: $RIGFLOW_PLUGIN_PATH/[^ ]*" "$tmp/ld" | sed 's/.*\///' | sort -u
    grep -v '^ *[0-9]*:' "$tmp/ld" >"$tmp/err"
    return $code
}

first=$(opened "$rigflow" validate "$tmp/p.json") || bad "validate with no index yet"
check '[ "$first" = "$(printf "a_good.so\nb_dup.so\nc_names.so")" ]' \
    "with no index yet, every plugin is opened (opened: $(echo $first))"
check 'grep -q "duplicate node type .test.source.*a_good.so" "$tmp/err"' \
    "the duplicate's refusal is reported"
check '[ -f "$tmp/index" ] && [ "$(grep -c "\.so	" "$tmp/index")" = 2 ]' \
    "the index has the two plugins admitted (the refused one is not entered)"

second=$(opened "$rigflow" validate "$tmp/p.json") || bad "validate with the index"
check '[ "$second" = "$(printf "a_good.so\nb_dup.so")" ]' \
    "with the index, the plugin the pipeline does not use stays closed (opened: $(echo $second))"
check 'grep -q "duplicate node type .test.source.*a_good.so" "$tmp/err"' \
    "a refused plugin is still opened and reported on every run"

(cd "$tmp" && opened "$rigflow" run --profile "$tmp/p.json" >/dev/null) || bad "run with the index"
check '[ "$(cat "$tmp/out.txt" 2>/dev/null)" = 7 ]' "the pipeline runs with the index"
check 'grep -q "^profile: validation, plugins opened: [0-9.]* ms" "$tmp/err"' \
    "run --profile times the validation (where plugins are opened)"

RIGFLOW_PLUGIN_INDEX= "$rigflow" plugins >"$tmp/plugins-noindex" 2>"$tmp/refused-noindex"
listed=$(opened "$rigflow" plugins)
check 'cmp -s "$tmp/out" "$tmp/plugins-noindex"' "rigflow plugins lists the same with the index as without"
check '[ "$listed" = "$(printf "a_good.so\nb_dup.so\nc_names.so")" ]' "rigflow plugins opens every plugin"
check 'grep -q "^rigflow: refused: .*b_dup.so" "$tmp/err"' "rigflow plugins reports the refusal"

# A replaced plugin file is opened again and entered anew.
before=$(grep c_names "$tmp/index")
cp "$plugins/c_names.so" "$tmp/c.new" && mv "$tmp/c.new" "$plugins/c_names.so"
third=$(opened "$rigflow" validate "$tmp/p.json")
check 'echo "$third" | grep -q c_names.so' "a replaced plugin is opened again"
check '[ -n "$(grep c_names "$tmp/index")" ] && [ "$(grep c_names "$tmp/index")" != "$before" ]' \
    "and its index entry is renewed"

# An index that lies (the test types moved to the names matcher's file) changes no answer.
sed -i '/a_good/s/\ttest\.[a-z]*//g; /a_good/s/$/\ttest.elsewhere/' "$tmp/index"
sed -i '/c_names/s/$/\ttest.source\ttest.sink/' "$tmp/index"
(cd "$tmp" && rm -f out.txt && "$rigflow" -q run "$tmp/p.json" >/dev/null 2>"$tmp/err")
check '[ "$(cat "$tmp/out.txt" 2>/dev/null)" = 7 ]' "a lying index: the pipeline still finds its node types"

# A plugin the index vouches for but that is refused when opened for the pipeline: the refusal
# is reported as an error of the run, beside the node type it could not provide.
late="$tmp/late"
mkdir "$late"
cp "$fixtures/fx_initfail.so" "$late/a_init.so"
if read -r dev ino size mt ct < <(stat -c '%d %i %s %.9Y %.9Z' "$late/a_init.so" 2>/dev/null); then
    printf '%s\n%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$(head -1 "$tmp/index")" "$late/a_init.so" \
        "$dev" "$ino" "$size" "${mt/./}" "${ct/./}" org.rigflow.test.init test.source >"$tmp/late-index"
    RIGFLOW_PLUGIN_PATH="$late" RIGFLOW_PLUGIN_INDEX="$tmp/late-index" \
        "$rigflow" validate "$tmp/p.json" >/dev/null 2>"$tmp/err"
    code=$?
    check '[ "$code" = 3 ] && grep -q "error: .*a_init.so: plugin failed to initialise: the fixture.s licence file is missing" "$tmp/err"' \
        "a plugin refused when opened on demand: its reason is an error of the run (exit $code)"
else
    echo "# SKIP: GNU stat unavailable: the late refusal is not tested"
fi

# Another host's index is ignored and rewritten; RIGFLOW_PLUGIN_INDEX= turns the index off.
sed -i '1s/.*/rigflow-plugin-index 1 abi 0.0.0/' "$tmp/index"
"$rigflow" validate "$tmp/p.json" >/dev/null 2>&1
check 'head -1 "$tmp/index" | grep -qv "abi 0.0.0"' "an index for another ABI is replaced"
rm -f "$tmp/index"
off=$(RIGFLOW_PLUGIN_INDEX= opened "$rigflow" validate "$tmp/p.json")
check '[ ! -e "$tmp/index" ] && [ "$(echo "$off" | wc -l)" = 3 ]' \
    "RIGFLOW_PLUGIN_INDEX= writes no index and opens every plugin"

# The bundled plugins: the retarget pipeline validates with a fresh index and with a known one.
if [ -d "$RF_BUILDDIR/plugins" ]; then
    export RIGFLOW_PLUGIN_PATH="$RF_BUILDDIR/plugins"
    rm -f "$tmp/index"
    files=(-p source.path=walk.bvh -p target.path=figure.glb -p export.path="$tmp/o.glb")
    "$rigflow" validate "${RF_SRCDIR:?}/pipelines/retarget.json" "${files[@]}" >/dev/null 2>"$tmp/err"
    check '[ $? = 0 ]' "pipelines/retarget.json validates while the index is made"
    bundled=$(opened "$rigflow" validate "$RF_SRCDIR/pipelines/retarget.json" "${files[@]}")
    check '! echo "$bundled" | grep -q rig-general.so && echo "$bundled" | grep -q retarget.so' \
        "with the index it opens retarget.so and not rig-general.so (opened: $(echo $bundled))"
fi

echo "# $pass passed, $fail failed"
[ "$fail" = 0 ]
