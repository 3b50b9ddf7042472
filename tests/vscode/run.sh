#!/usr/bin/env bash
# Run by tests/editor_setups.rs inside `unshare -rnpf`: a private network namespace (VS Code
# and Chromium reach nothing but each other on its loopback) and process namespace (all
# they start ends with this script). Starts code-server (VS Code's server and extension
# host) on the workspace WS with the extensions in EXT, opens its workbench in headless
# Chromium (the extension host runs for a connected window), and waits for the test
# driver extension to write WS/done.txt. Usage: run.sh WS EXT DATA
set -euo pipefail
ws=$1 ext=$2 data=$3
ip link set lo up
code-server --auth none --bind-addr 127.0.0.1:0 --user-data-dir "$data" \
  --extensions-dir "$ext" --disable-telemetry --disable-update-check \
  --disable-workspace-trust --disable-getting-started-override "$ws" >"$data/code-server.log" 2>&1 &
server=$!
browser=
trap 'kill $server ${browser:-} 2>/dev/null || true' EXIT
url=
for _ in $(seq 200); do
  url=$(grep -o 'http://127.0.0.1:[0-9]*/' "$data/code-server.log" || true)
  [[ -n $url ]] && break
  sleep 0.05
done
[[ -n $url ]] || { cat "$data/code-server.log" >&2; echo "code-server did not listen" >&2; exit 1; }
chromium --headless=new --no-sandbox --disable-gpu --no-first-run \
  --user-data-dir="$data/chromium" "${url}?folder=$ws" >"$data/chromium.log" 2>&1 &
browser=$!
for _ in $(seq 1600); do
  [[ -f $ws/done.txt ]] && exit 0
  sleep 0.05
done
echo "no result from the extension host in 80 s" >&2
cat "$data/code-server.log" >&2
exit 1
