#!/usr/bin/env bash
# Installs every build and test dependency of depath from Debian 12 packages.
# Idempotent: does nothing when all packages are already installed.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
mapfile -t pkgs < <(grep -vE '^\s*(#|$)' "$here/packages.txt")
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#pkgs[@]} packages present"
else
  echo "setup: installing ${missing[*]}"
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
# npm: Debian's package only when the installed nodejs does not bring its own (see packages.txt).
if ! command -v npm >/dev/null; then
  echo "setup: installing npm"
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends npm
fi
# The web view's npm packages, exactly as locked in web/package-lock.json (the only time the
# npm registry is used; the build then works offline).
if [ ! -d "$here/../web/node_modules/esbuild" ]; then
  echo "setup: npm ci in web/"
  (cd "$here/../web" && npm ci --no-audit --no-fund)
fi
