#!/usr/bin/env bash
# Installs what the tests need beyond the Rust toolchain:
# - Debian's headless-capable Chromium, which the browser tests drive to
#   render the animation and live pages and screenshot them (skipped when
#   /usr/bin/chromium is already there);
# - the engine compiled to WebAssembly (scripts/build-web.sh), which the
#   live page tests embed;
# - real robots and Pinocchio's dynamics of them (scripts/fetch-robots.sh).
set -euo pipefail
cd "$(dirname "$0")/.."

if [ -x /usr/bin/chromium ]; then
    echo "chromium already installed: $(/usr/bin/chromium --version 2>/dev/null || echo unknown version)"
else
    SUDO=""
    if [ "$(id -u)" -ne 0 ]; then
        SUDO="sudo"
    fi
    export DEBIAN_FRONTEND=noninteractive
    $SUDO apt-get update -qq
    $SUDO apt-get install -y -qq --no-install-recommends chromium
    /usr/bin/chromium --version
fi

scripts/build-web.sh

# Real robots (example-robot-data) and Pinocchio's dynamics of them, for
# the URDF conformance tests; they skip with a message without them.
scripts/fetch-robots.sh
