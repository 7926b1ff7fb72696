#!/usr/bin/env bash
# Create (or refresh) the project virtual environment and install wallsim with its
# test extra. Prefers CPython 3.12 (numpy 2.5 / scipy 1.18 need >= 3.12); falls back to
# any python3 >= 3.11, where pip resolves numpy 2.4 / scipy 1.17 within our ranges.
set -euo pipefail
venv="${1:-.venv}"

pick_python() {
  local c
  for c in "${WALLSIM_PYTHON:-}" \
           $(ls -d "$(pyenv root 2>/dev/null || echo /nonexistent)"/versions/3.12*/bin/python 2>/dev/null) \
           python3.12 python3.13 \
           $(ls -d "$(pyenv root 2>/dev/null || echo /nonexistent)"/versions/3.13*/bin/python 2>/dev/null) \
           python3.11 python3; do
    [ -n "$c" ] || continue
    if "$c" -c 'import sys; sys.exit(0 if sys.version_info >= (3, 11) else 1)' >/dev/null 2>&1; then
      echo "$c"; return 0
    fi
  done
  echo "no Python >= 3.11 found; set WALLSIM_PYTHON=/path/to/python3.12" >&2
  return 1
}

if [ ! -x "$venv/bin/python" ]; then
  py=$(pick_python)
  echo "creating $venv with $("$py" --version 2>&1) ($py)" >&2
  "$py" -m venv "$venv"
fi
"$venv/bin/python" -m pip install --quiet --upgrade pip
"$venv/bin/python" -m pip install --quiet -e ".[test]"
