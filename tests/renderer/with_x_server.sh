#!/usr/bin/env bash
# with_x_server.sh PROGRAM [ARGS...]: runs PROGRAM with an X server of its own (Xvfb;
# Mesa's llvmpipe gives OpenGL 4.5), so that the GL tests run the same on a desktop,
# a server and in CI, and side by side under ctest -j. Xvfb picks a free display
# itself (-displayfd), which xvfb-run -a does not do safely for parallel runs.
set -euo pipefail
dir=$(mktemp -d "${TMPDIR:-/tmp}/marionette_x.XXXXXX")
Xvfb -displayfd 3 -screen 0 1024x768x24 -nolisten tcp 3>"$dir/display" 2>"$dir/xvfb.log" &
server=$!
cleanup() { kill "$server" 2>/dev/null || true; wait "$server" 2>/dev/null || true; rm -rf "$dir"; }
trap cleanup EXIT
for _ in $(seq 200); do  # up to 10 s
  [ -s "$dir/display" ] && break
  if ! kill -0 "$server" 2>/dev/null; then
    echo "with_x_server.sh: Xvfb did not start:" >&2; cat "$dir/xvfb.log" >&2; exit 1
  fi
  sleep 0.05
done
[ -s "$dir/display" ] || { echo "with_x_server.sh: Xvfb gave no display within 10 s" >&2; exit 1; }
DISPLAY=":$(head -n1 "$dir/display")" "$@"
