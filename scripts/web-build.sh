#!/usr/bin/env bash
# Builds aograph's web page (crates/web) into a static folder any file host can serve:
#   OUT/index.html, OUT/page.js, OUT/pkg/aograph_web.js, OUT/pkg/aograph_web_bg.wasm
# Usage: bash scripts/web-build.sh [OUT]   (default out/web)
# Installs what a fresh machine lacks: the wasm32 target (rustup) and wasm-bindgen-cli at the
# version Cargo.lock pins for the wasm-bindgen crate (the two must match exactly).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-out/web}"
if command -v rustup >/dev/null; then
    rustup target add wasm32-unknown-unknown >/dev/null 2>&1 || true
fi
version="$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/"/, "", $3); print $3 }' Cargo.lock)"
if ! wasm-bindgen --version 2>/dev/null | grep -qx "wasm-bindgen $version"; then
    echo "web-build: installing wasm-bindgen-cli $version (once per machine)" >&2
    # Not --locked: its own lock file pins a webpki-roots release crates.io no longer serves.
    # --force: cargo's record of installed binaries may outlive the binaries themselves.
    cargo install --quiet --force wasm-bindgen-cli --version "=$version"
fi
started=$SECONDS
# The dev profile: dependencies are built at opt-level 2 (Cargo.toml), fast enough to run,
# and it shares nothing with the native build's artifacts either way (another target).
cargo build --locked --quiet -p aograph-web --lib --target wasm32-unknown-unknown
rm -rf "$out"
mkdir -p "$out"
wasm-bindgen --target web --no-typescript --out-dir "$out/pkg" \
    target/wasm32-unknown-unknown/debug/aograph_web.wasm
cp crates/web/www/index.html crates/web/www/page.js "$out/"
echo "web-build: $out ($(du -sh "$out" | cut -f1)) in $((SECONDS - started)) s; serve it with e.g. python3 -m http.server -d $out"
