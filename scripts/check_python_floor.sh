#!/usr/bin/env bash
# The Python floor pyproject declares (requires-python) must be true: every tracked
# Python file must compile with that interpreter. Compiled in memory (no __pycache__);
# skipped, with a line saying so, where no such interpreter is installed.
set -euo pipefail
cd "$(dirname "$0")/.."
floor=$(sed -n 's/^requires-python = ">=\([0-9][0-9.]*\)".*/\1/p' pyproject.toml)
py=""
for c in "python$floor" $(ls -d "$(pyenv root 2>/dev/null || echo /nonexistent)"/versions/"$floor".*/bin/python 2>/dev/null); do
  if "$c" -c "import sys; sys.exit(0 if sys.version_info[:2] == tuple(map(int, '$floor'.split('.'))) else 1)" \
       >/dev/null 2>&1; then py=$c; break; fi
done
if [ -z "$py" ]; then
  echo "python floor $floor: no such interpreter here, not checked" >&2
  exit 0
fi
git ls-files -z '*.py' | xargs -0 "$py" -c '
import sys
bad = []
for path in sys.argv[1:]:
    try:
        compile(open(path, "rb").read(), path, "exec", dont_inherit=True)
    except SyntaxError as err:
        bad.append(f"{path}:{err.lineno}: {err.msg}")
print("\n".join(bad) or f"python floor {sys.version.split()[0]}: {len(sys.argv) - 1} files compile", file=sys.stderr)
sys.exit(1 if bad else 0)'
