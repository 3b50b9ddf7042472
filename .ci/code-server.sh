#!/usr/bin/env bash
# Installs VS Code's server and extension host as the npm package code-server (4.100.3,
# with Code 1.100.3) for tests/editor_setups.rs, from npm and Debian only. Its own
# postinstall downloads prebuilt binaries (ripgrep, from outside the registries), so the
# steps are done here instead: Debian's ripgrep stands in, native modules are compiled
# against the installed node's headers. code-server 4.100 needs node 20; with another node
# nothing is installed and the VS Code test prints `skipped: code-server not found`.
set -euo pipefail
version=4.100.3
if code-server --version 2>/dev/null | grep -q "^$version "; then
  exit 0
fi
major=$(node -p 'process.versions.node.split(".")[0]')
nodedir=$(dirname "$(dirname "$(command -v node)")")
if [[ $major != 20 || ! -f $nodedir/include/node/node.h ]]; then
  echo "code-server $version needs node 20 with its headers (have node $major in $nodedir):" \
    "not installed, the VS Code check will be skipped" >&2
  exit 0
fi
apt-get update
DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
  g++ make pkg-config python3 libkrb5-dev ripgrep
export npm_config_nodedir=$nodedir npm_config_yes=true
npm install -g --no-audit --no-fund --ignore-scripts "code-server@$version"
root=$(npm root -g)/code-server
cd "$root/lib/vscode"
npm install --omit=dev --no-audit --no-fund --ignore-scripts
mkdir -p node_modules/@vscode/ripgrep/bin
ln -sf "$(command -v rg)" node_modules/@vscode/ripgrep/bin/rg
npm rebuild
# What code-server's postinstall.sh does besides.
ln -sfn node_modules node_modules.asar
(cd bin/remote-cli && ln -sf code-linux.sh code-server)
(cd bin/helpers && ln -sf browser-linux.sh browser.sh)
(cd extensions && npm install --omit=dev --no-audit --no-fund)
cd "$root"
npm rebuild argon2
code-server --version
