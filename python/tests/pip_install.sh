#!/usr/bin/env bash
# `pip install SOURCE` as a user runs it (ctest python.pip_install): a fresh venv made from interpreter $1, the
# checkout $2 built by scikit-build-core (pyproject.toml) into it, then the pytest suite against the installed module,
# run from the work folder $3 so that nothing is imported from the source or build tree. Exit 77 (skipped) where PyPI
# cannot be reached; a failing build or test fails.
set -u
python=$1 source=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
venv=$work/venv
"$python" -m venv "$venv" || {
  echo "skipped: $python -m venv failed (python3-venv)"
  exit 77
}
# The build backend and the test tools first: only they need the network.
"$venv/bin/pip" install -q --disable-pip-version-check scikit-build-core==0.11.6 numpy==2.4.6 pytest==8.4.2 || {
  echo "skipped: scikit-build-core, numpy and pytest could not be installed (pip)"
  exit 77
}
set -e
"$venv/bin/pip" install --disable-pip-version-check --no-build-isolation -q "$source"
cd "$work"
"$venv/bin/python" -c "import clradiosity, sys; print('installed:', clradiosity.__file__)"
exec "$venv/bin/python" -m pytest -q -p no:cacheprovider --rootdir "$work" "$source/python/tests"
