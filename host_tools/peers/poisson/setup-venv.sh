#!/usr/bin/env bash
# Creates (once) the Python venv the screened Poisson peer runs in, with a
# pinned Open3D from PyPI. Idempotent: a venv that already imports the
# pinned version is left alone. Prints the venv's python on stdout.
# Usage: host_tools/peers/poisson/setup-venv.sh VENV_DIR
set -euo pipefail
venv=${1:?usage: setup-venv.sh VENV_DIR}
open3d_version=0.19.0
numpy_spec='numpy<2.3'

ok() {
  "$venv/bin/python" -c "import open3d, sys; sys.exit(open3d.__version__ != '$open3d_version')" \
    >/dev/null 2>&1
}
if [ -x "$venv/bin/python" ] && ok; then
  echo "$venv/bin/python"
  exit 0
fi

# The system python3 may be a pyenv shim; prefer it, fall back to Debian's.
for py in python3 /usr/bin/python3; do
  command -v "$py" >/dev/null || continue
  rm -rf "$venv"
  if "$py" -m venv "$venv" >&2 &&
     "$venv/bin/python" -m pip install -q --disable-pip-version-check \
       "open3d==$open3d_version" "$numpy_spec" >&2 && ok; then
    echo "$venv/bin/python"
    exit 0
  fi
  echo "pitvol: open3d $open3d_version did not install with $py" >&2
done
rm -rf "$venv"
echo "pitvol: no python here can install open3d $open3d_version (see above)" >&2
exit 1
