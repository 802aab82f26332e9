#!/usr/bin/env bash
# Create or refresh the project's virtual environment (.venv) from requirements/lock.txt.
# Idempotent: it reinstalls only when the lock or pyproject.toml changed since the last run.
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=${VENV:-.venv}
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
stamp_id=$(cat requirements/lock.txt pyproject.toml | sha256sum | cut -c1-16)
stamp="$VENV/.installed-$stamp_id"
if [ -f "$stamp" ]; then
  exit 0
fi
echo "bootstrap: installing the environment into $VENV from requirements/lock.txt" >&2
[ -x "$VENV/bin/python" ] || "$PY" -m venv "$VENV"
"$VENV/bin/python" -m pip install --quiet --disable-pip-version-check -r requirements/lock.txt
"$VENV/bin/python" -m pip install --quiet --disable-pip-version-check --no-deps -e .
rm -f "$VENV"/.installed-*
touch "$stamp"
echo "bootstrap: done" >&2
