#!/usr/bin/env bash
# The real programs the tests run, installed where missing: GNU parallel,
# POV-Ray, Chromium and lavapipe, Mesa's software Vulkan driver, with the
# Vulkan loader (Debian; `render --device gpu` runs on it where there is
# no GPU), Rust's wasm32-unknown-unknown target (rustup, for
# the browser playground), openjd-cli, kubernetes-validate and Mitsuba 3 (PyPI, in a
# virtual environment under target/test-tools, where the tests look), and
# the Khronos glTF-Validator and puppeteer-core (npm, under
# target/test-tools/npm; Node from Debian where there is none). The
# README's test command runs this, then `cargo test` with
# NFFKIT_TEST_TOOLS=required, so that a test needing one of them fails
# instead of skipping.
set -euo pipefail
cd "$(dirname "$0")/.."

# Debian packages, by the command each provides.
debian() { # COMMAND PACKAGE...
  command -v "$1" >/dev/null && return
  shift
  apt_install "$@"
}
apt_install() { # PACKAGE...
  if [ "$(id -u)" = 0 ]; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q "$@" >/dev/null 2>&1 ||
      { apt-get update -q >/dev/null && DEBIAN_FRONTEND=noninteractive apt-get install -y -q "$@" >/dev/null; }
  elif command -v sudo >/dev/null; then
    sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -q "$@" >/dev/null
  fi
}
debian parallel parallel
if ! ls /usr/share/vulkan/icd.d/lvp_icd.*.json >/dev/null 2>&1; then
  apt_install mesa-vulkan-drivers libvulkan1
fi
debian povray povray
debian chromium chromium
if command -v rustup >/dev/null && ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
  rustup target add wasm32-unknown-unknown
fi
debian node nodejs npm
debian npm npm
npm_modules=target/test-tools/npm/node_modules
if [ ! -f $npm_modules/gltf-validator/package.json ] || [ ! -f $npm_modules/puppeteer-core/package.json ]; then
  mkdir -p target/test-tools/npm
  npm install --prefix target/test-tools/npm --no-audit --no-fund --silent gltf-validator puppeteer-core
fi
venv=target/test-tools
if [ ! -x "$venv/bin/openjd" ] || [ ! -x "$venv/bin/kubernetes-validate" ] ||
  ! "$venv/bin/python" -c "import mitsuba" 2>/dev/null; then
  if ! python3 -m venv "$venv" 2>/dev/null; then
    # Debian keeps venv apart.
    if [ "$(id -u)" = 0 ]; then
      apt-get install -y -q python3-venv >/dev/null 2>&1 ||
        { apt-get update -q >/dev/null && apt-get install -y -q python3-venv >/dev/null; }
    fi
    rm -rf "$venv"
    python3 -m venv "$venv"
  fi
  "$venv/bin/pip" install -q --disable-pip-version-check openjd-cli kubernetes-validate mitsuba
fi
