# The Khronos glTF-Validator from the shell tests: source this file after defining ok and ko
# (the counters of the test), then call `gltf_valid FILE` for each glTF/GLB and end the test with
# `gltf_exit "$fail"`. A missing validator is a visible skip, never a pass: each validation it
# could not make is counted, and the test then exits 77 (automake's SKIP) unless something failed.
gltf_validate_js="${RF_SRCDIR:-.}/tests/gltf/validate.js"
gltf_node="${RF_NODE:-node}"
gltf_skipped=0

gltf_valid() {
    if ! command -v "$gltf_node" >/dev/null 2>&1; then
        gltf_skipped=$((gltf_skipped + 1)); echo "SKIP: no node: $1 not validated"; return
    fi
    "$gltf_node" "$gltf_validate_js" "$1"
    case $? in
    0) ok "glTF-Validator accepts $(basename "$1")" ;;
    77) gltf_skipped=$((gltf_skipped + 1)); echo "SKIP: glTF-Validator not installed: $1 not validated" ;;
    *) ko "glTF-Validator rejects $1" ;;
    esac
}

# gltf_exit FAILED: exit 1 on failures, else 77 when a validation was skipped, else 0.
gltf_exit() {
    [ "$1" -eq 0 ] || exit 1
    if [ "$gltf_skipped" -gt 0 ]; then echo "SKIP: $gltf_skipped glTF validations not made"; exit 77; fi
    exit 0
}
