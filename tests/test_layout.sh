#!/usr/bin/env bash
# The layout's dependency direction (doc/architecture.md), checked on every source's includes:
#   sdk/        includes only the SDK's public headers (rigflow/...) and files of its own folder;
#   plugins/N/  the same: the SDK and its own folder, never the host or another plugin;
#   framework/  the SDK and its own files, never a plugin's.
# A quoted include must name a file that exists where that rule allows it.
set -u
src="${RF_SRCDIR:?}"
cd "$src" || exit 99
pass=0 fail=0
bad() { fail=$((fail + 1)); echo "not ok - $1"; }

# check FILE: every quoted include of FILE is allowed for its area.
check() {
    local f=$1 dir inc area
    dir=$(dirname "$f")
    case $f in sdk/*) area=sdk ;; plugins/*) area=plugin ;; framework/*) area=host ;; esac
    while IFS= read -r inc; do
        case $inc in
        config.h) continue ;;
        rigflow/*) [ -f "sdk/include/$inc" ] && continue ;;
        */*) ;;
        *) [ -f "$dir/$inc" ] && continue ;;
        esac
        # the host may also include its own headers from framework/
        [ "$area" = host ] && [ -f "framework/$inc" ] && continue
        bad "$f includes \"$inc\", outside what $area code may include"
        return
    done < <(sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*"\([^"]*\)".*/\1/p' "$f")
    # Installed headers include each other as <rigflow/...> only.
    if [ "$area" = sdk ]; then
        while IFS= read -r inc; do
            case $inc in rigflow/*) [ -f "sdk/include/$inc" ] || { bad "$f includes <$inc>, which the SDK lacks"; return; } ;; esac
        done < <(sed -n 's/^[[:space:]]*#[[:space:]]*include[[:space:]]*<\([^>]*\)>.*/\1/p' "$f")
    fi
    pass=$((pass + 1))
}

while IFS= read -r f; do check "$f"; done < <(find sdk plugins framework -name '*.[ch]' | sort)

# Build rules: no plugin or SDK target puts the host's or another plugin's folder on its path.
while IFS= read -r mk; do
    if grep -n -e '-I\$(top_srcdir)/framework' -e '-I\$(top_srcdir)/plugins' -e 'HOST_CPPFLAGS' "$mk" >/dev/null; then
        bad "$mk adds the host's or the plugins' folders to an include path"
    else
        pass=$((pass + 1))
    fi
done < <(find sdk plugins -name local.mk | sort)

echo "$pass files keep to the layout, $fail do not"
[ "$fail" = 0 ]
