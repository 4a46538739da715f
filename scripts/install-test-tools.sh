#!/usr/bin/env bash
# The real programs the farm tests run, installed where missing: GNU
# parallel (Debian) and openjd-cli and kubernetes-validate (PyPI, in a
# virtual environment under target/test-tools, where the tests look). The
# README's test command runs this, then `cargo test` with
# NFFKIT_TEST_TOOLS=required, so that a test needing one of them fails
# instead of skipping.
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v parallel >/dev/null; then
  if [ "$(id -u)" = 0 ]; then
    apt-get install -y -q parallel >/dev/null 2>&1 ||
      { apt-get update -q >/dev/null && apt-get install -y -q parallel >/dev/null; }
  elif command -v sudo >/dev/null; then
    sudo apt-get install -y -q parallel >/dev/null
  fi
fi
venv=target/test-tools
if [ ! -x "$venv/bin/openjd" ] || [ ! -x "$venv/bin/kubernetes-validate" ]; then
  if ! python3 -m venv "$venv" 2>/dev/null; then
    # Debian keeps venv apart.
    if [ "$(id -u)" = 0 ]; then
      apt-get install -y -q python3-venv >/dev/null 2>&1 ||
        { apt-get update -q >/dev/null && apt-get install -y -q python3-venv >/dev/null; }
    fi
    rm -rf "$venv"
    python3 -m venv "$venv"
  fi
  "$venv/bin/pip" install -q --disable-pip-version-check openjd-cli kubernetes-validate
fi
