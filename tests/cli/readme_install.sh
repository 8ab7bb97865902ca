#!/usr/bin/env bash
# The README's build-then-install sequence, verbatim but for the prefix: `cmake --workflow --preset release` (which
# builds the clradiosity binary alone) and then `cmake --install build/release --prefix PREFIX`. The install must
# succeed without the Python module that build does not make, install no half of it, and give a binary that runs
# from the prefix. Slow (a full release build): ctest label `slow`.
# Usage: readme_install.sh SOURCE_DIR CMAKE
set -uo pipefail
source_dir=$1 cmake=$2
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
cd "$source_dir" || fail "no source dir $source_dir"
"$cmake" --workflow --preset release >"$prefix/build.log" 2>&1 || fail "cmake --workflow --preset release: $(tail -3 "$prefix/build.log")"
"$cmake" --install build/release --prefix "$prefix/p" >"$prefix/install.log" 2>&1 ||
  fail "cmake --install build/release: $(tail -3 "$prefix/install.log")"
[ -x "$prefix/p/bin/clradiosity" ] || fail "no bin/clradiosity"
[ -f "$prefix/p/share/clradiosity/scenes/cornell-box.xml" ] || fail "no bundled scenes"
if find "$prefix/p" -path '*site-packages/clradiosity/__init__.py' | grep -q .; then
  find "$prefix/p" -name '_clradiosity*.so' | grep -q . || fail "half a Python module installed (its .py files without the extension)"
fi
(cd /tmp && "$prefix/p/bin/clradiosity" --version) >/dev/null || fail "the installed binary does not run"
echo PASS
