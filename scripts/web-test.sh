#!/usr/bin/env bash
# aograph's web page in headless Chromium (CI): builds the page (scripts/web-build.sh), runs the
# same frames natively (crates/web/examples/native_ao.rs, on the machine's Vulkan device made
# with WebGPU's default limits), then loads the page for three techniques and compares
# (scripts/web_check.py), and once more for a .glb it fetches. Installs Debian's chromium when it is missing.
# Usage: bash scripts/web-test.sh [WORK_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
work="${1:-$(mktemp -d)}"
if ! command -v chromium >/dev/null; then
    echo "web-test: installing Debian's chromium" >&2
    sudo_if_needed=""
    if [ "$(id -u)" != 0 ] && command -v sudo >/dev/null; then sudo_if_needed=sudo; fi
    $sudo_if_needed env DEBIAN_FRONTEND=noninteractive apt-get install -y -q chromium >/dev/null
fi
started=$SECONDS
bash scripts/web-build.sh "$work/site"
built=$SECONDS
cargo run --locked --quiet -p aograph-web --example native_ao -- "$work/native" gtao hbao mssao
# A glTF fetched by URL: the vendored CesiumMan (a skinned .glb) served beside the page.
cp tests/scenes/CesiumMan.glb "$work/site/"
python3 scripts/web_check.py "$work/site" "$work/native" --gltf CesiumMan.glb
echo "web-test: wasm build $((built - started)) s, native run and browser test $((SECONDS - built)) s"
