#!/usr/bin/env bash
# Builds the engine and the Dyad front end as WebAssembly (crates/multibody-web)
# for `multibody live`, which embeds it in the page. Adds Rust's wasm32 target
# first when it is missing. The module lands where the command looks for it:
# target/wasm32-unknown-unknown/web/multibody_web.wasm (under CARGO_TARGET_DIR
# when that is set).
set -euo pipefail
cd "$(dirname "$0")/.."

if ! rustup target list --installed 2>/dev/null | grep -qx wasm32-unknown-unknown; then
    rustup target add wasm32-unknown-unknown
fi
cargo build --profile web -p multibody-web --target wasm32-unknown-unknown
module="${CARGO_TARGET_DIR:-target}/wasm32-unknown-unknown/web/multibody_web.wasm"
echo "built $module ($(wc -c < "$module") bytes)"
