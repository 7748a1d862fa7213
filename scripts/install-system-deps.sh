#!/usr/bin/env bash
# Debian packages eigengait needs: EGL/Mesa for offscreen rendering, Chromium for the studio's browser tests.
# Installs only what is missing; needs root (or sudo) the first time.
set -euo pipefail
packages=(libegl1 libegl-mesa0 libgl1-mesa-dri libglx-mesa0 libgles2 fonts-dejavu-core)
if [[ "${1:-}" == "--with-browser" ]]; then packages+=(chromium); fi
missing=()
for p in "${packages[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
((${#missing[@]} == 0)) && exit 0
echo "installing Debian packages: ${missing[*]}"
SUDO=""; [[ $(id -u) -ne 0 ]] && SUDO="sudo"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
