#!/usr/bin/env bash
# The Python module's pytest suite (ctest python.pytest) on the package folder $3 (the build tree's, where the
# extension sits beside python/clradiosity/*.py), with the tests' venv $2 made from interpreter $1. Exit 77 (skipped)
# where the venv cannot be made.
set -u
python=$1 venv=$2 package_root=$3
here=$(cd "$(dirname "$0")" && pwd)
bash "$here/../../.ci/install-python-test-deps" "$venv" "$python" >/dev/null
"$venv/bin/python" -c "import pytest, numpy" 2>/dev/null || {
  echo "skipped: pytest and numpy could not be installed into $venv (pip)"
  exit 77
}
cd "$here"
PYTHONPATH="$package_root" exec "$venv/bin/python" -m pytest -q -p no:cacheprovider .
