#!/usr/bin/env bash
# ctest report.browser: the report page in headless Chromium (browser_check.py), run by the tests' venv $2 made from
# interpreter $1 (numpy, for the build tree's Python module that reads the EXRs). Exit 77 (skipped) where the venv
# cannot be made; browser_check.py skips likewise where no browser is installed.
set -u
python=$1 venv=$2
shift 2
here=$(cd "$(dirname "$0")" && pwd)
bash "$here/../../.ci/install-python-test-deps" "$venv" "$python" >/dev/null
"$venv/bin/python" -c "import numpy" 2>/dev/null || {
  echo "skipped: numpy could not be installed into $venv (pip)"
  exit 77
}
exec "$venv/bin/python" "$here/browser_check.py" "$@"
