#!/usr/bin/env bash
# Create or refresh the project's virtual environment (.venv) from requirements/lock.txt.
# Idempotent: it reinstalls only when the lock or pyproject.toml changed since the last run.
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${VENV:-.venv}
UV_VERSION=0.13.9
PY=${PYTHON:-}
if [ -z "$PY" ]; then
  for cand in python3.11 python3; do
    if command -v "$cand" >/dev/null 2>&1 &&
       "$cand" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))'; then
      PY=$cand; break
    fi
  done
fi
if [ -z "$PY" ]; then
  echo "bootstrap: Python 3.11 is required (set PYTHON=/path/to/python3.11)" >&2
  exit 1
fi
# JupyterLab opens the .md chapters as notebooks (jupytext as their default viewer): the same
# settings file as Binder's, in this environment's JupyterLab settings (also for older venvs).
lab_settings() {
  local dir="$VENV/share/jupyter/lab/settings"
  if ! cmp -s binder/overrides.json "$dir/overrides.json" 2>/dev/null; then
    mkdir -p "$dir" && cp binder/overrides.json "$dir/overrides.json"
  fi
}
# MathJax 4, which the site serves itself (book/_ext/mathjax4.py: pinned npm tarballs, checked
# against their sha512), unpacked once into the environment; nothing happens when it is there.
mathjax() {
  "$VENV/bin/python" book/_ext/mathjax4.py "$VENV" >/dev/null
}
# the version is part of the stamp: the editable install's metadata carries it, and the chapters'
# first cell compares it with the book's
stamp_id=$(cat requirements/lock.txt requirements/overrides.txt pyproject.toml src/fusioncenter/__init__.py \
  | sha256sum | cut -c1-16)
stamp="$VENV/.installed-$stamp_id"
if [ -f "$stamp" ]; then
  [ -x "$VENV/bin/python" ] && lab_settings && mathjax
  exit 0
fi
echo "bootstrap: installing the environment into $VENV from requirements/lock.txt" >&2
[ -x "$VENV/bin/python" ] || "$PY" -m venv "$VENV"
# uv installs the same pins as pip, in parallel: about 10 s where pip took about 150 s on a fresh
# 2-core machine (issue 16). uv itself is pinned; where it cannot be had, pip does the install.
pip_q=("$VENV/bin/python" -m pip install --quiet --disable-pip-version-check)
if "${pip_q[@]}" "uv==$UV_VERSION" >/dev/null 2>&1 && [ -x "$VENV/bin/uv" ]; then
  uv_q=("$VENV/bin/uv" pip install --quiet --python "$VENV/bin/python")
  "${uv_q[@]}" -r requirements/lock.txt --override requirements/overrides.txt
  "${uv_q[@]}" --no-deps -e .
else
  echo "bootstrap: uv $UV_VERSION not available; installing with pip" >&2
  "${pip_q[@]}" -r requirements/lock.txt
  "${pip_q[@]}" --no-deps -e .
fi
lab_settings
mathjax
rm -f "$VENV"/.installed-*
touch "$stamp"
echo "bootstrap: done" >&2
