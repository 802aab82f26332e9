#!/usr/bin/env bash
# Re-resolve requirements/requirements.in into requirements/lock.txt in a throw-away venv.
# After it, update environment.yml's pins if they changed (tests/test_repository.py checks them).
set -euo pipefail
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3.11 -m venv "$tmp/venv"
"$tmp/venv/bin/python" -m pip install --quiet --disable-pip-version-check -r requirements/requirements.in
{
  echo "# Pinned with Python 3.11 by \`make lock\` from requirements/requirements.in. Do not edit by hand."
  "$tmp/venv/bin/python" -m pip freeze --disable-pip-version-check | grep -v '^-e '
} > requirements/lock.txt
echo "lock: wrote requirements/lock.txt ($(grep -vc '^#' requirements/lock.txt) packages)"
